"""The scatter of a result over fills built alike (the same configuration, other seeds): its
mean, standard deviation, range and characteristic value.

The characteristic value is the upper 95% fractile predicted from the n runs, as EN 1990
(Eurocode 0), Annex D.7.2 defines it for a normal population whose mean and standard deviation
are both unknown ("V_X unknown"): x_k = m + k_n s, k_n = t(0.95, n - 1) sqrt(1 + 1/n), with m the
mean, s the sample standard deviation and t Student's quantile (k_n = 3.37 for 3 runs, 2.33 for
5, 1.92 for 10, 1.64 for infinitely many: Annex D's table D1). It is an upper value: a load, a
penetration and a count of broken elements are unfavourable when large.
"""
import math

CHARACTERISTIC = ("upper 95% fractile of a normal population with unknown mean and standard deviation (EN 1990 Annex D.7.2): "
                  "mean + k_n s, k_n = t(0.95, n-1) sqrt(1 + 1/n)")
FRACTILE = 0.95


def k_n(n, fractile=FRACTILE):
    """EN 1990's k_n for n runs (n >= 2): t(fractile, n - 1) sqrt(1 + 1/n)."""
    from scipy.stats import t
    if not isinstance(n, int) or n < 2:
        raise ValueError(f"k_n: n must be a whole number >= 2 (a standard deviation needs two runs), got {n!r}")
    return float(t.ppf(fractile, n - 1)) * math.sqrt(1.0 + 1.0 / n)


def describe(values):
    """dict(n, mean, std, cv, min, max, k_n, characteristic) of the finite numbers among values
    (None and NaN left out: a run that did not finish); std is the sample standard deviation
    (n - 1), cv = std / |mean|; std, cv, k_n and characteristic are None below two values."""
    xs = [float(v) for v in values if v is not None and isinstance(v, (int, float)) and math.isfinite(v)]
    n = len(xs)
    out = dict(n=n, mean=None, std=None, cv=None, min=None, max=None, k_n=None, characteristic=None)
    if n == 0:
        return out
    m = sum(xs) / n
    out.update(mean=m, min=min(xs), max=max(xs))
    if n >= 2:
        s = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1))
        k = k_n(n)
        out.update(std=s, cv=s / abs(m) if m else None, k_n=k, characteristic=m + k * s)
    return out
