"""The nodes, one executable per module: ``joint_sim``, ``controller``, ``estimator``."""
__all__ = []
