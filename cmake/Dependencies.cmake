# Every dependency comes from a Debian 12 package (tools/install-deps.sh installs them).
find_package(Threads REQUIRED)
find_package(glm REQUIRED)
find_package(OpenEXR REQUIRED CONFIG)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(tinyobjloader REQUIRED)
find_package(CLI11 REQUIRED)
find_package(PNG REQUIRED)
find_package(embree 3 QUIET CONFIG)  # optional, bench-only: frameless bench rays compares with it
if(embree_FOUND)
  message(STATUS "Embree ${embree_VERSION} found: bench rays will compare against it")
endif()
