"""The low-pass filter of recorded impact forces: a zero-phase Butterworth filter, as impact
tests filter their accelerometer signals before they report a peak (the raw signal of a DEM
run chatters at the contacts' frequencies, far above the boulder's deceleration pulse)."""
import math

import numpy as np

CUTOFF_HZ = 300.0  # [Hz] the default cut-off: about SAE J211's channel class 180, kept for the boulder's rigid-body deceleration
ORDER = 4


def describe(cutoff_hz=CUTOFF_HZ, order=ORDER):
    """The filter in words, as the summaries state it."""
    return f"zero-phase Butterworth low-pass, order {order} (run forward and back), cut-off {cutoff_hz:g} Hz"


def low_pass(t, f, cutoff_hz=CUTOFF_HZ, order=ORDER):
    """f [any unit] sampled at the times t [s] (increasing), filtered by describe()'s filter: the
    samples are first put on an even grid of their mean interval (linear interpolation; the
    runner's records are evenly spaced to within a step), filtered, and read back at t. Within
    about 1/cutoff_hz of either end the filter has too few samples on one side: a force still
    high at the end of the records is filtered less there. Fewer
    than 3 x (order + 1) samples, or a cut-off at or above the Nyquist frequency: ValueError."""
    from scipy.signal import butter, sosfiltfilt
    t, f = np.asarray(t, dtype=float), np.asarray(f, dtype=float)
    if t.shape != f.shape or t.ndim != 1:
        raise ValueError("low_pass: t and f must be 1-D arrays of one length")
    if len(t) < 3 * (order + 1):
        raise ValueError(f"low_pass: {len(t)} samples are too few for an order-{order} filter (at least {3 * (order + 1)})")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(f)) and np.all(np.diff(t) > 0)):
        raise ValueError("low_pass: the times must increase and the values be finite")
    dt = (t[-1] - t[0]) / (len(t) - 1)
    nyquist = 0.5 / dt
    if not (0 < cutoff_hz < nyquist) or not math.isfinite(cutoff_hz):
        raise ValueError(f"low_pass: the cut-off {cutoff_hz:g} Hz must be below the Nyquist frequency {nyquist:.4g} Hz of the records "
                         f"(one every {1e3 * dt:.3g} ms)")
    grid = t[0] + dt * np.arange(len(t))
    even = np.interp(grid, t, f)
    sos = butter(order, cutoff_hz, btype="low", fs=1.0 / dt, output="sos")
    return np.interp(t, grid, sosfiltfilt(sos, even))
