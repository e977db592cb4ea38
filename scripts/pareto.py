"""The Pareto front of points where smaller is better on both axes, and a scatter plot that marks
it: the report's size against lookup time (report.py) and error against memory (views.py).

A point is on the front when no other point is at least as good on both axes and better on
one. Two points at the same place do not dominate each other, so both are on the front: a tie
is a real alternative (two schemes of one size and speed), not a point to drop at random.
"""


def dominates(a, b):
    """Whether point `a` (x, y) is at least as small as `b` on both axes and smaller on one."""
    return a[0] <= b[0] and a[1] <= b[1] and (a[0] < b[0] or a[1] < b[1])


def pareto_front(points):
    """Indices of the non-dominated points of `points` (x, y), by x then y. Quadratic, which is
    plenty for the tens of points of a plot and reads as the definition."""
    front = [i for i, p in enumerate(points) if not any(dominates(q, p) for q in points)]
    return sorted(front, key=lambda i: (points[i][0], points[i][1], i))


def plot_front(axes, points, labels, groups=None):
    """Draws `points` on `axes`, each numbered, with the front in red and joined in x order;
    the legend beside the axes gives each number's label. `groups` (a key per point; None: one
    group) splits the points into sets compared only among themselves, each with its own
    front, such as the resolutions of one plot. Returns {group: its front's indices}."""
    groups = groups or [None] * len(points)
    fronts = {}
    for key in dict.fromkeys(groups):
        members = [i for i, group in enumerate(groups) if group == key]
        fronts[key] = [members[j] for j in pareto_front([points[i] for i in members])]
    on_front = {i for front in fronts.values() for i in front}
    for number, ((x, y), label) in enumerate(zip(points, labels), start=1):
        best = number - 1 in on_front
        axes.plot([x], [y], linestyle="none", marker="o", markersize=7 if best else 5,
                  color="tab:red" if best else "tab:grey", label=f"{number}: {label}")
        axes.annotate(str(number), (x, y), textcoords="offset points", xytext=(4, 4),
                      fontsize="small", fontweight="bold" if best else "normal")
    for n, front in enumerate(fronts.values()):
        axes.plot([points[i][0] for i in front], [points[i][1] for i in front], color="tab:red",
                  linewidth=1, zorder=0, label=None if n else "Pareto front")
    # Beside the axes: with many points a legend inside hides them.
    axes.legend(fontsize="x-small", loc="upper left", bbox_to_anchor=(1.02, 1))
    axes.grid(True, which="major", alpha=0.3)
    return fronts
