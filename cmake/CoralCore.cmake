# The ROS-free runtime libraries, one per concern. Included by the catkin build and by the
# plain CMake core-only build (-DCORAL_CORE_ONLY=ON), so none of them ever needs ROS. The
# evaluation toolbox (eval: tools and tests only) is toolbox/CMakeLists.txt.
# Dependencies point one way only (README.md, Architecture):
#   online -> radar -> coral        eval -> rio -> radar -> coral
#   rio -> config                   (config: the parameter tree; ros links it too)
find_package(Eigen3 REQUIRED)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs)
# Ceres (Debian's libceres-dev). Its CMake target points at the static, non-PIC libceres.a;
# the nodelet plugin is a shared library, so link the shared libceres.so (and glog, which
# Ceres' headers use) directly.
find_package(Ceres REQUIRED)
find_library(CORAL_CERES_LIBRARY NAMES libceres.so ceres REQUIRED)
find_library(CORAL_GLOG_LIBRARY NAMES glog REQUIRED)
find_package(yaml-cpp REQUIRED)  # parameter trees from YAML files (config/yaml_tree.hpp)
find_package(PCL REQUIRED COMPONENTS common io registration)
find_package(Threads REQUIRED)  # CoralConfig::threads (std::thread)

set(CORAL_WARNINGS -Wall -Wextra)

# coral_add_library(<name> <dir> [ROOT <folder>] DEPS <targets...>): a static,
# position-independent library from <folder>/src/<dir>/*.cpp (folder: the source tree, or
# toolbox) with <folder>/include (linked into the nodelet plugin, hence PIC).
function(coral_add_library name dir)
  cmake_parse_arguments(ARG "" "ROOT" "DEPS" ${ARGN})
  if(NOT ARG_ROOT)
    set(ARG_ROOT ${PROJECT_SOURCE_DIR})
  endif()
  file(GLOB srcs CONFIGURE_DEPENDS ${ARG_ROOT}/src/${dir}/*.cpp)
  add_library(${name} STATIC ${srcs})
  set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
                                            $<BUILD_INTERFACE:${ARG_ROOT}/include>)
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  target_compile_options(${name} PRIVATE ${CORAL_WARNINGS})
endfunction()

# The parameter tree every config loader reads (CoralNodelet, RioNodelet, presets, rio YAML):
# depends on nothing of ours, so any library can use it.
coral_add_library(coral_introspection_config config DEPS yaml-cpp)
target_include_directories(coral_introspection_config SYSTEM PUBLIC ${YAML_CPP_INCLUDE_DIR})
coral_add_library(coral_introspection_coral coral DEPS Threads::Threads)
# The moment kernel's vector and scalar paths must round |p - q|^2 alike (no fused
# multiply-add where the code does not ask for one): both then count the same neighbours.
set_source_files_properties(${PROJECT_SOURCE_DIR}/src/coral/moments_kernel.cpp PROPERTIES
                            COMPILE_OPTIONS -ffp-contract=off)
# Third-party headers as SYSTEM so the warning flags report only our own code.
target_include_directories(coral_introspection_coral SYSTEM PUBLIC ${EIGEN3_INCLUDE_DIR})
coral_add_library(coral_introspection_radar radar DEPS coral_introspection_coral ${OpenCV_LIBS})
target_include_directories(coral_introspection_radar SYSTEM PUBLIC ${OpenCV_INCLUDE_DIRS})
coral_add_library(coral_introspection_online online DEPS coral_introspection_radar)
coral_add_library(coral_introspection_rio rio DEPS coral_introspection_radar
                  coral_introspection_config ${CORAL_CERES_LIBRARY} ${CORAL_GLOG_LIBRARY})
target_include_directories(coral_introspection_rio SYSTEM PUBLIC ${CERES_INCLUDE_DIRS})

set(CORAL_CORE_LIBRARIES coral_introspection_config coral_introspection_coral
    coral_introspection_radar coral_introspection_online coral_introspection_rio)

# Tests find ../shared/data next to the real (symlink-resolved) source tree, or
# $CORAL_DATA_DIR; the support header skips with a message when neither exists.
get_filename_component(CORAL_REAL_SOURCE_DIR ${PROJECT_SOURCE_DIR} REALPATH)
# The path reaches the tests through one object (coral_test::sourceDir, test/support), not a
# definition on every test: the test objects then do not depend on where the clone lives and
# the compiler cache reuses them for another clone (scripts/env.sh). Built only for tests.
add_library(coral_test_source_dir STATIC EXCLUDE_FROM_ALL ${PROJECT_SOURCE_DIR}/test/support/source_dir.cpp)
target_include_directories(coral_test_source_dir PRIVATE ${PROJECT_SOURCE_DIR}/test)
target_compile_definitions(coral_test_source_dir PRIVATE CORAL_SOURCE_DIR="${CORAL_REAL_SOURCE_DIR}")
# ROS-free gtests: test/<library>/test_*.cpp; each links its library and, for fixtures and
# datasets, eval.
file(GLOB CORAL_CORE_TESTS CONFIGURE_DEPENDS
     ${PROJECT_SOURCE_DIR}/test/coral/test_*.cpp ${PROJECT_SOURCE_DIR}/test/radar/test_*.cpp
     ${PROJECT_SOURCE_DIR}/test/online/test_*.cpp ${PROJECT_SOURCE_DIR}/test/eval/test_*.cpp
     ${PROJECT_SOURCE_DIR}/test/rio/test_*.cpp ${PROJECT_SOURCE_DIR}/test/config/test_*.cpp)
set(CORAL_CORE_TEST_LIBRARIES coral_introspection_online coral_introspection_eval
    coral_introspection_rio)
