# Every dependency comes from a Debian 12 package (tools/install-deps.sh installs them).
find_package(Threads REQUIRED)
find_package(glm REQUIRED)
find_package(OpenEXR REQUIRED CONFIG)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(tinyobjloader REQUIRED)
find_package(CLI11 REQUIRED)
find_package(PNG REQUIRED)
find_package(JPEG REQUIRED)      # texture decoding (libjpeg-turbo)
find_package(ZLIB REQUIRED)      # gzip-encoded NRRD volumes (zlib1g-dev, also libpng's)
find_package(TinyGLTF REQUIRED CONFIG)  # glTF 2.0 models
find_package(MPI REQUIRED COMPONENTS C)  # the cluster (Open MPI: libopenmpi-dev, openmpi-bin)
find_package(embree 3 QUIET CONFIG)  # optional, bench-only: frameless bench rays compares with it
if(embree_FOUND)
  message(STATUS "Embree ${embree_VERSION} found: bench rays will compare against it")
endif()
# Viewer and headless capture: GLFW for the window, OSMesa for offscreen GL (GL entry points are
# fetched through each context's own loader, so libGL itself is never linked).
find_package(glfw3 3.3 REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(OSMESA REQUIRED IMPORTED_TARGET osmesa)
# OpenVDB files: Blosc decompresses the leaves OpenVDB 10 writes by default (libblosc-dev); the
# reader is our own (core/io/volume_vdb.h), so OpenVDB itself is not linked.
pkg_check_modules(BLOSC REQUIRED IMPORTED_TARGET blosc)
# The Python module (pybind11-dev, python3-dev, python3-numpy): Debian's /usr/bin/python3.
set(PYBIND11_FINDPYTHON ON)
set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the module is built for")
find_package(pybind11 2.6 QUIET CONFIG)
if(NOT pybind11_FOUND)
  message(STATUS "pybind11 not found: the Python module is not built (tools/install-deps.sh installs pybind11-dev)")
endif()
