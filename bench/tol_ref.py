"""Analytic references of the benchmark (Euler-Bernoulli cantilever, steel)."""
import math

E, RHO, G = 200e9, 7850.0, 9.81


def cantilever_reference(load, length, radius, force=1.0):
    """Tip deflection [m]: P L^3 / (3 E I) (tip load) or q L^4 / (8 E I) (self-weight)."""
    I = math.pi * radius ** 4 / 4
    if load == "tip":
        return force * length ** 3 / (3 * E * I)
    q = RHO * math.pi * radius ** 2 * G
    return q * length ** 4 / (8 * E * I)
