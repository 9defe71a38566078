# The scene runner behind `ffdaabb run`, `bench` and `soak` (runner.h): loads a scene with the
# command line's overrides, steps it, and summarises timings, counters and the meshes'
# interpenetration as the --stats JSON. The Python module's `run` links it too, so that both
# give the same statistics under the same names.
find_package(nlohmann_json REQUIRED)
find_package(fmt REQUIRED)
if(NOT TARGET ffdaabb_bench_common)
  add_subdirectory(${PROJECT_SOURCE_DIR}/bench/common ${PROJECT_BINARY_DIR}/bench/common)
endif()
add_library(ffdaabb_runner STATIC ${CMAKE_CURRENT_LIST_DIR}/runner.cpp)
target_include_directories(ffdaabb_runner PUBLIC ${CMAKE_CURRENT_LIST_DIR}
                           PRIVATE ${PROJECT_SOURCE_DIR}/src)
target_link_libraries(ffdaabb_runner PUBLIC ffdaabb_content ffdaabb_bench_common
                      nlohmann_json::nlohmann_json PRIVATE fmt::fmt)
ffd_warnings(ffdaabb_runner)
