# Locate the YADE 2023.02a source tree (headers only; Debian ships none).
# Order: -DYADE_SOURCE_DIR / $YADE_SOURCE_DIR, then ~/.cache/yade-src/2023.02a.
# Downloading is the job of scripts/setup (it verifies the sha256); the build only
# checks and stops with a message saying exactly what to provide.
set(_yade_hint "$ENV{YADE_SOURCE_DIR}")
if(NOT YADE_SOURCE_DIR)
  if(_yade_hint)
    set(YADE_SOURCE_DIR "${_yade_hint}")
  else()
    set(YADE_SOURCE_DIR "$ENV{HOME}/.cache/yade-src/${YADE_VERSION_TAG}")
  endif()
endif()
if(NOT EXISTS "${YADE_SOURCE_DIR}/core/Omega.hpp")
  message(FATAL_ERROR
    "YADE ${YADE_VERSION_TAG} headers not found in '${YADE_SOURCE_DIR}'.\n"
    "Provide them in one of these ways:\n"
    "  * run scripts/setup (downloads trunk-${YADE_VERSION_TAG}.tar.gz and checks its sha256), or\n"
    "  * unpack YADE's source at tag ${YADE_VERSION_TAG} and pass -DYADE_SOURCE_DIR=<dir> or set YADE_SOURCE_DIR, or\n"
    "  * from a local git clone of YADE carrying the tag: mkdir -p <dir> && git -C <clone> archive ${YADE_VERSION_TAG} | tar -x -C <dir>, then pass <dir> as YADE_SOURCE_DIR\n"
    "Never commit that source tree.")
endif()
message(STATUS "YADE headers: ${YADE_SOURCE_DIR}")
