include(GoogleTest)

# dorado_add_test(NAME SOURCES... LIBS ...): one GoogleTest executable per file, registered with ctest.
function(dorado_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} dorado_test_scenes dorado_warnings GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE
    DORADO_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    DORADO_TEST_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/data"
    DORADO_SYSTEM_PYTHON="/usr/bin/python3")
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
endfunction()
