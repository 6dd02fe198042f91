# libFuzzer harnesses test/fuzz/fuzz_<name>.cpp -> executables fuzz_<name> (clang only),
# enabled with -DCORAL_FUZZ=ON. scripts/ci/fuzz.sh builds them with the sanitizers and
# -fsanitize=fuzzer-no-link in CMAKE_CXX_FLAGS (coverage of the libraries) and runs them.
# fuzz_cloud_conversion needs the ROS adapters, so it is skipped in the core-only build.
file(GLOB CORAL_FUZZERS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/fuzz/fuzz_*.cpp)
foreach(fuzz_src ${CORAL_FUZZERS})
  get_filename_component(fuzz_name ${fuzz_src} NAME_WE)
  if(fuzz_name STREQUAL "fuzz_cloud_conversion")
    if(CORAL_CORE_ONLY)
      continue()
    endif()
    set(fuzz_libs coral_introspection_ros)
  else()
    set(fuzz_libs coral_introspection_radar)
  endif()
  add_executable(${fuzz_name} ${fuzz_src})
  target_link_libraries(${fuzz_name} ${fuzz_libs})
  target_compile_options(${fuzz_name} PRIVATE -fsanitize=fuzzer ${CORAL_WARNINGS})
  target_link_options(${fuzz_name} PRIVATE -fsanitize=fuzzer)
  if(NOT CORAL_CORE_ONLY)
    add_dependencies(${fuzz_name} ${PROJECT_NAME}_generate_messages_cpp)
  endif()
endforeach()
