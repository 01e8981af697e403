# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
ament_python package setup for friction_joint.

ROS 2 packages (rclpy, message packages) are deliberately not in
``install_requires``: in a ROS workspace rosdep/colcon provide them, and on a
plain Python install ``requirements.txt`` pins their PyPI wheels.

The version lives in one place, ``package.xml`` (as ROS tooling expects); it
is read from there, so ``importlib.metadata.version('friction_joint')`` of an
installed package agrees with it.
"""
from glob import glob
import os
from xml.etree import ElementTree

from setuptools import find_packages, setup

package_name = 'friction_joint'
here = os.path.dirname(os.path.abspath(__file__))


def package_version():
    """Return the ``<version>`` of ``package.xml`` beside this file."""
    root = ElementTree.parse(os.path.join(here, 'package.xml')).getroot()
    version = (root.findtext('version') or '').strip()
    if not version:
        raise RuntimeError('package.xml has no <version>')
    return version


setup(
    name=package_name,
    version=package_version(),
    packages=find_packages(exclude=['test', 'test.*']),
    # py.typed: the package's annotations are for type checkers too (PEP 561)
    package_data={package_name: ['ros/fastdds.xml', 'py.typed']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/config', glob('config/*.yaml')),
        ('share/' + package_name + '/launch', glob('launch/*.launch.py')),
    ],
    install_requires=['setuptools', 'numpy', 'scipy', 'PyYAML', 'matplotlib', 'markdown'],
    extras_require={'fast': ['numba'], 'bags': ['rosbags', 'mcap', 'mcap-ros2-support'],
                    'test': ['pytest']},      # 'test': colcon test runs pytest, not unittest
    zip_safe=True,
    maintainer='friction_joint maintainers',
    maintainer_email='maintainers@friction-joint.invalid',
    description=('Simulated Harmonic Drive joint with thermal- and load-dependent dynamic '
                 'friction.'),
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
