"""The binomial interval the study scripts quote (inject-study.py, injection-study.py)."""
import math


def wilson(k, n, z=1.0):
    """Wilson score interval of k successes in n trials (z = 1: 68.27 %); [0, 1] when n = 0."""
    if n == 0:
        return 0.0, 1.0
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return max(0.0, centre - half), min(1.0, centre + half)
