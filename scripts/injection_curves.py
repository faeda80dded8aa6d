"""What the injection-study scripts share (inject-study.py, injection-study.py): the binomial
interval they quote and the LENS_SCORE threshold at a density of spurious candidates."""
import math

import numpy as np


def wilson(k, n, z=1.0):
    """Wilson score interval of k successes in n trials (z = 1: 68.27 %); [0, 1] when n = 0."""
    if n == 0:
        return 0.0, 1.0
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return max(0.0, centre - half), min(1.0, centre + half)


def threshold_at(spurious_scores, area_deg2, per_deg2):
    """The lowest LENS_SCORE threshold that keeps the spurious candidates at most per_deg2 of
    area_deg2 (-inf: every candidate, also when per_deg2 is None): just above the highest
    spurious score left out. A count exactly at the level is allowed a relative 1e-9 (9 in
    0.018 deg2 is 500 per deg2, though it divides to a hair above)."""
    if per_deg2 is None:
        return -np.inf
    scores = np.sort(np.asarray(spurious_scores, dtype=float))[::-1]
    allowed = int(np.floor(per_deg2 * area_deg2 * (1 + 1e-9)))
    return np.nextafter(scores[allowed], np.inf) if allowed < len(scores) else -np.inf
