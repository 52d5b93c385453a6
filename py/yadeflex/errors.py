"""The exception of a run that became unstable."""


class Unstable(ValueError, RuntimeError):
    """A run became unstable: a body's motion is no longer finite (the scene check, the
    integrator), FlexGuard found a runaway step or energy created, or the critical time step
    collapsed below FlexTimeStepper.minDtFraction of its reference. The message names the body.
    A ValueError (as the scene check's other refusals) and a RuntimeError (as FlexGuard's stop
    before): code that caught either still catches it. The main job and studies end such a run
    with status 'unstable', exit status 2."""
