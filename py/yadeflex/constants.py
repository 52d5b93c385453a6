"""Physical constants of every scene, model and output (SI units)."""

G = 9.81  # [m/s2] standard gravity: the scenes' default and the impact speed of a drop, sqrt(2 G h)
