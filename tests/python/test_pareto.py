"""scripts/pareto.py: the non-dominated points (smaller is better on both axes), ties, and the
fronts a plot marks per group."""

import unittest

import support  # noqa: F401 (scripts/ on the path)
from pareto import dominates, pareto_front, plot_front


class Front(unittest.TestCase):

    def test_the_non_dominated_points_by_size(self):
        points = [(4, 1), (1, 5), (3, 4), (2, 3), (2, 6), (5, 5)]
        # (3, 4) is beaten by (2, 3); (2, 6) by (1, 5); (5, 5) by everything but (1, 5) and
        # (2, 6), which are as large on one axis and smaller on the other.
        self.assertEqual(pareto_front(points), [1, 3, 0])

    def test_no_points_and_one_point(self):
        self.assertEqual(pareto_front([]), [])
        self.assertEqual(pareto_front([(7, 7)]), [0])

    def test_a_point_at_the_same_place_as_another_is_on_the_front_with_it(self):
        self.assertEqual(pareto_front([(2, 2), (1, 3), (2, 2)]), [1, 0, 2])
        self.assertFalse(dominates((2, 2), (2, 2)))

    def test_equal_on_one_axis_and_worse_on_the_other_is_dominated(self):
        self.assertEqual(pareto_front([(1, 3), (1, 2)]), [1])  # same size, slower
        self.assertEqual(pareto_front([(2, 1), (1, 1)]), [1])  # same speed, larger
        self.assertTrue(dominates((1, 2), (1, 3)))

    def test_a_plot_finds_a_front_per_group(self):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        figure, axes = plt.subplots()
        self.addCleanup(plt.close, figure)
        points = [(1, 9), (2, 2), (3, 3), (10, 10), (20, 5), (30, 50)]
        fronts = plot_front(axes, points, list("abcdef"), [1, 1, 1, 2, 2, 2])
        self.assertEqual(fronts, {1: [0, 1], 2: [3, 4]})
        self.assertEqual(plot_front(axes, points, list("abcdef")), {None: [0, 1]})


if __name__ == "__main__":
    unittest.main()
