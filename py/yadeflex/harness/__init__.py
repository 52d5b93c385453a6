"""The validation and benchmark harness: reference scenes (scenes, membrane_scenes), tensile tests
(tensile), the reference cases and their verdicts (cases, verdict), the fill calibration
(calibration) and the stability suite (stability). Not needed to build or run a structure."""
