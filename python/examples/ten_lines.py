"""Example 1: ten lines with numpy. A box sunk into a fixed floor and a
hull overlapping it, repaired by the smallest mass-weighted correction."""

import numpy as np

import constraint_stabilization as cs

scene = cs.Scene()
scene.add_body(cs.box([2.0, 2.0, 0.1]), fixed=True)  # the floor, top at z = 0
scene.add_body(cs.box([0.1, 0.1, 0.1]), mass=1.0)
scene.add_body(cs.hull(np.random.default_rng(0).normal(size=(20, 3)) * 0.1), mass=0.5)
poses = np.array([[0, 0, -0.1, 1, 0, 0, 0], [0, 0, 0.05, 1, 0, 0, 0], [0.1, 0, 0.15, 1, 0, 0, 0]])  # wxyz
fixed, report = cs.stabilize(scene, poses, quaternion_order="wxyz")
print(report.status, f"depth {report.depth_before:.3g} -> {report.depth_after:.3g} m in {report.times['total'] * 1e3:.2f} ms")
print(np.round(fixed, 4))
