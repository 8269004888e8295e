# Runs PROGRAM OUT and fails unless OUT equals EXPECTED (a generated page that must stay current).
execute_process(COMMAND ${PROGRAM} ${OUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${PROGRAM} failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT} ${EXPECTED} RESULT_VARIABLE diff)
if(NOT diff EQUAL 0)
  message(FATAL_ERROR "${EXPECTED} is stale: rebuild the target regenerate-docs and commit the page")
endif()
