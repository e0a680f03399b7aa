# cmake -P: install BUILD_DIR into WORK_DIR/prefix, build PROJECT_DIR against it, run it.
#   MAPPER      ON: also build and run mapper_consumer (every library; not with DORADO_CORE_ONLY)
#   COMPONENTS  the optional readers built (find_package(dorado COMPONENTS ...) must succeed)
#   MISSING     those left out (find_package(dorado COMPONENTS ...) must fail)
# COMPONENTS and MISSING are comma-separated (and COMPONENTS stays so on to the project).
string(REPLACE "," ";" MISSING "${MISSING}")
file(REMOVE_RECURSE ${WORK_DIR})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed (${status}): ${ARGN}")
  endif()
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
# Only the install prefix (and the system's packages) is searched: not this build tree.
set(configure ${CMAKE_COMMAND} -S ${PROJECT_DIR} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON
    -DCMAKE_CXX_COMPILER_LAUNCHER= -DPython3_EXECUTABLE=${PYTHON} -DDORADO_CONSUMER_MAPPER=${MAPPER})
run(${configure} -B ${WORK_DIR}/build -DDORADO_CONSUMER_COMPONENTS=${COMPONENTS})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/consumer)
if(MAPPER)
  run(${WORK_DIR}/build/mapper_consumer ${WORK_DIR})
endif()
foreach(component ${MISSING})
  execute_process(COMMAND ${configure} -B ${WORK_DIR}/missing_${component}
    -DDORADO_CONSUMER_COMPONENTS=${component} RESULT_VARIABLE status OUTPUT_QUIET ERROR_QUIET)
  if(status EQUAL 0)
    message(FATAL_ERROR "find_package(dorado COMPONENTS ${component}) succeeded; it was not built")
  endif()
  message(STATUS "find_package(dorado COMPONENTS ${component}) fails, as it should: not built")
endforeach()
