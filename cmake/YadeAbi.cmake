# The ONE place that must match Debian's yade 2023.02a binary (yade-double).
# A mismatch here silently changes class layouts (Body, State, Scene, ...): the smoke
# test tests/yade/test_smoke.py (save / load / continue) is the guard.
set(YADE_VERSION_TAG "2023.02a")
set(YADE_ABI_DEFINITIONS
    YADE_BOOST_LOG BOOST_LOG_DYN_LINK MAX_LOG_LEVEL=5 YADE_COMPLEX_MP
    YADE_REAL_BIT=64 YADE_REAL_DEC=15 YADE_VTK YADE_OPENMP YADE_GTS YADE_OPENGL
    YADE_QT5 QT_NO_KEYWORDS YADE_CGAL CGAL_DISABLE_ROUNDING_MATH_CHECK YADE_MPI
    YADE_LS_DEM YADE_FEM THERMAL PARTIALSAT YADE_POTENTIAL_PARTICLES YADE_GL2PS
    YADE_ODEINT)
# YADE's CMakeLists adds these unless built with VECTORIZE (Debian's is not): Eigen types
# are then unaligned, which changes the layout of State, Body, ... (measured: State::mass
# 16 bytes off without them). The kernel uses them too, since its structs (quaternions)
# cross into the adapter.
set(YADE_EIGEN_DEFINITIONS EIGEN_DONT_VECTORIZE EIGEN_DONT_ALIGN EIGEN_DISABLE_UNALIGNED_ARRAY_ASSERT)
# -frounding-math is in YADE's flags for CGAL's interval arithmetic; no CGAL code is compiled here
# and it is not an ABI setting, so it is left out (it slows the element loop ~2x).
set(YADE_ABI_COMPILE_OPTIONS -fopenmp)
# Debian's plugin directory: YADE dlopens every lib*.so found there at start.
set(YADE_PLUGIN_DIR_DEFAULT "/usr/lib/x86_64-linux-gnu/yade-double")
