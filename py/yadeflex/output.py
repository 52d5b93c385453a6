"""Results, by what they are: VTK time series for ParaView (yadeflex.vtk_frames, describing the
files; their forked writers: yadeflex.vtk_writers), the energy CSV and CSV reading
(yadeflex.energy_csv), plots (yadeflex.plots). This module gathers what scripts use."""
from .energy_csv import EnergyRecorder, read_csv  # noqa: F401
from .plots import ENERGY_ALPHA, plot_energy, plot_timeseries  # noqa: F401
from .vtk_frames import GROUPS, VtkRecorder, real_contacts, scene_groups, write_vtk_snapshot  # noqa: F401
