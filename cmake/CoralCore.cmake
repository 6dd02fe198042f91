# The ROS-free core library: every src/core/*.cpp. Included by the catkin build and by the
# plain-CMake core-only build (-DCORAL_CORE_ONLY=ON), so the core never needs ROS.
find_package(Eigen3 REQUIRED)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs)

file(GLOB CORAL_CORE_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/core/*.cpp)
add_library(coral_introspection_core STATIC ${CORAL_CORE_SOURCES})
set_target_properties(coral_introspection_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
target_include_directories(coral_introspection_core PUBLIC ${PROJECT_SOURCE_DIR}/include)
# Third-party headers as SYSTEM so -Wall -Wextra reports only our own code.
target_include_directories(coral_introspection_core SYSTEM PUBLIC
  ${EIGEN3_INCLUDE_DIR} ${OpenCV_INCLUDE_DIRS})
target_link_libraries(coral_introspection_core PUBLIC ${OpenCV_LIBS})
target_compile_options(coral_introspection_core PRIVATE -Wall -Wextra)

# Tests find ../shared/data next to the real (symlink-resolved) source tree, or
# $CORAL_DATA_DIR; the support header skips with a message when neither exists.
get_filename_component(CORAL_REAL_SOURCE_DIR ${PROJECT_SOURCE_DIR} REALPATH)
set(CORAL_TEST_DEFINITIONS CORAL_SOURCE_DIR="${CORAL_REAL_SOURCE_DIR}")
file(GLOB CORAL_CORE_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/core/test_*.cpp)
