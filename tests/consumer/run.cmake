# Builds tests/consumer/project against sglab::runtime, either through an
# installed package (MODE=find_package) or add_subdirectory, and runs it.
# Arguments: SGLAB_SOURCE, WORK, MODE.
file(REMOVE_RECURSE ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message("${out}")
endfunction()
set(project ${CMAKE_CURRENT_LIST_DIR}/project)
if(MODE STREQUAL "find_package")
  run(${CMAKE_COMMAND} -S ${SGLAB_SOURCE} -B ${WORK}/sglab-build -DSGLAB_RUNTIME_ONLY=ON
      -DCMAKE_INSTALL_PREFIX=${WORK}/prefix)
  run(${CMAKE_COMMAND} --install ${WORK}/sglab-build)
  run(${CMAKE_COMMAND} -S ${project} -B ${WORK}/consumer-build -DCMAKE_PREFIX_PATH=${WORK}/prefix)
else()
  run(${CMAKE_COMMAND} -S ${project} -B ${WORK}/consumer-build -DSGLAB_MODE=add_subdirectory
      -DSGLAB_SOURCE=${SGLAB_SOURCE})
endif()
run(${CMAKE_COMMAND} --build ${WORK}/consumer-build)
run(${WORK}/consumer-build/consumer)
