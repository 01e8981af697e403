"""ament_python package setup for friction_joint.

ROS 2 packages (rclpy, message packages) are deliberately not in
``install_requires``: in a ROS workspace rosdep/colcon provide them, and on a
plain Python install ``requirements.txt`` pins their PyPI wheels.
"""
from glob import glob

from setuptools import find_packages, setup

package_name = 'friction_joint'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test', 'test.*']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/config', glob('config/*.yaml')),
    ],
    install_requires=['setuptools', 'numpy', 'scipy', 'PyYAML', 'matplotlib'],
    extras_require={'fast': ['numba'], 'bags': ['rosbags', 'mcap', 'mcap-ros2-support']},
    zip_safe=True,
    maintainer='friction_joint maintainers',
    maintainer_email='maintainers@friction-joint.invalid',
    description='Simulated Harmonic Drive joint with thermal- and load-dependent dynamic friction.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'friction_joint = friction_joint.cli:main',
            'joint_sim = friction_joint.ros.nodes.joint_sim:main',
            'controller = friction_joint.ros.nodes.controller:main',
            'estimator = friction_joint.ros.nodes.estimator:main',
            'record = friction_joint.cli.record:main',
            'replay = friction_joint.cli.replay:main',
        ],
    },
)
