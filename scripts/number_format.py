"""The one number formatter of the Python scripts: the harness's table numbers
(harness/table_number.cpp, formatSignificant in harness/progress.cpp) step for step, so that a
table cell reads the same whichever side printed it. Both are held to
tests/golden/number_format.tsv."""

import math

MISSING = "–"  # a cell without a value, as the harness's tables print it


def _round_half_away(value):
    """C's round(): halves away from zero (Python's round() goes to even)."""
    whole = math.floor(abs(value))
    if abs(value) - whole >= 0.5:
        whole += 1
    return math.copysign(whole, value)


def significant(value, digits=3):
    """`value` to `digits` significant digits in fixed notation ("0.0517", "13.0", "1048576");
    MISSING for None and "?" for a value that is not finite, as the harness prints them."""
    if value is None:
        return MISSING
    if not math.isfinite(value):
        return "?"
    if value == 0:
        return "0"

    def decimals_for(v):
        return min(max(digits - 1 - math.floor(math.log10(abs(v))), 0), 15)

    decimals = decimals_for(value)
    # Rounding may carry into a new leading digit (99.96 → 100.0): then one decimal fewer.
    scale = math.pow(10.0, decimals)
    rounded = _round_half_away(value * scale) / scale
    if rounded != 0:
        decimals = min(decimals, decimals_for(rounded))
    return f"{value:.{decimals}f}"


def integer(value):
    """A count shown whole ("22241"); MISSING for None and "?" for a value that is not finite."""
    if value is None:
        return MISSING
    if not math.isfinite(value):
        return "?"
    return f"{value:.0f}"


# The kinds of tests/golden/number_format.tsv the scripts print; its "count" (an SI prefix, as
# "12.3M") only the harness prints.
KINDS = {"significant": significant, "integer": integer}
