"""Statistics the scenes share: the Student-t interval of a mean."""

import numpy as np
from scipy import stats


def t_quantile(level, dof):
    """The quantile q of Student's t with `dof` degrees of freedom for which
    mean ± q·SE is a two-sided interval of confidence `level`."""
    return stats.t.ppf(0.5 + level / 2, dof)


def mean_t_ci(values, level=0.95):
    """Mean and the half width of its Student-t interval (nan for n < 2)."""
    values = np.asarray(values, dtype=float)
    n = values.size
    if n < 2:
        return (float(values.mean()) if n else np.nan), np.nan
    half = t_quantile(level, n - 1) * values.std(ddof=1) / np.sqrt(n)
    return float(values.mean()), float(half)
