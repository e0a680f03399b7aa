#!/usr/bin/python3
"""Fig. 7's close views show what they name (scripts/plot_benchmark.py, fig7_insets): on a 200 m
loop, `end` is a small view around the ground truth where the estimates end, also when one
estimate drifted 60 m off (listed instead of zooming out to the whole drive)."""
import math
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import plot_benchmark  # noqa: E402


def loop_ground_truth():
    """A 100 s drive, 1 m/s around a circle of 100 m diameter and beyond: starts at (0, 0)."""
    t = np.arange(0.0, 100.0, 0.1)
    angle = t / 50.0  # 1 m/s on a 50 m radius
    rows = np.zeros((len(t), 8))
    rows[:, 0] = t
    rows[:, 1] = 50.0 * np.sin(angle)
    rows[:, 2] = 50.0 * (1.0 - np.cos(angle))
    rows[:, 7] = 1.0
    return rows


def contains(view, point):
    (x0, x1), (y0, y1) = view
    return x0 <= point[0] <= x1 and y0 <= point[1] <= y1


def width(view):
    return view[0][1] - view[0][0]


class Fig7Insets(unittest.TestCase):
    def setUp(self):
        self.gt = loop_ground_truth()
        self.gt_end = self.gt[-1, 1:3]  # the estimates end at the last stamp
        self.drive = max(np.ptp(self.gt[:, 1]), np.ptp(self.gt[:, 2]))

    def test_end_is_a_close_view_around_the_ground_truths_end(self):
        views = plot_benchmark.fig7_insets(self.gt, {
            "Dopp": (0.0, 99.9, self.gt_end + [1.0, -0.5]),
            "IMU": (0.0, 99.9, self.gt_end + [-2.0, 1.5])})
        end = views["end"]
        self.assertTrue(contains(end, self.gt_end))
        self.assertTrue(contains(end, self.gt_end + [1.0, -0.5]))
        self.assertTrue(contains(end, self.gt_end + [-2.0, 1.5]))
        self.assertLess(width(end), 0.25 * self.drive)  # not the whole drive
        self.assertTrue(contains(views["start"], [0.0, 0.0]))
        self.assertFalse(contains(views["start"], self.gt_end))  # the drive ends 80 m away
        self.assertEqual(views["off_view"], [])

    def test_an_estimate_that_drifted_off_is_listed_not_zoomed_to(self):
        far = self.gt_end + [60.0, 0.0]
        views = plot_benchmark.fig7_insets(self.gt, {
            "Dopp": (0.0, 99.9, self.gt_end + [1.0, 0.0]), "NP": (0.0, 99.9, far)})
        self.assertEqual(views["off_view"], ["NP"])
        self.assertFalse(contains(views["end"], far))
        self.assertTrue(contains(views["end"], self.gt_end + [1.0, 0.0]))
        self.assertLess(width(views["end"]), 0.25 * self.drive)

    def test_end_follows_the_estimates_last_stamp_not_the_ground_truths(self):
        # Ground truth recorded 60 s past the estimates: the end view is where they stopped.
        views = plot_benchmark.fig7_insets(self.gt, {"Dopp": (0.0, 40.0, self.gt[400, 1:3])})
        self.assertTrue(contains(views["end"], self.gt[400, 1:3]))
        self.assertFalse(contains(views["end"], self.gt_end))
        self.assertTrue(math.isclose(width(views["end"]), width(views["start"])))


if __name__ == "__main__":
    unittest.main()
