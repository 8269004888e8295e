# Installs dqkit to a scratch prefix, then builds and runs a consumer with find_package and with
# pkg-config. Fails on any error.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed: ${ARGN}\n${out}\n${err}")
  endif()
endfunction()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/dqkit -DCMAKE_INSTALL_PREFIX=${prefix}
    -DDQKIT_BUILD_TESTS=OFF -DDQKIT_BUILD_BENCHMARKS=OFF -DDQKIT_BUILD_EXAMPLES=OFF -DDQKIT_BUILD_TOOLS=OFF)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/dqkit -j 2)
run(${CMAKE_COMMAND} --install ${WORK_DIR}/dqkit)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer/project -B ${WORK_DIR}/consumer -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_CXX_COMPILER=${CXX})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
run(${WORK_DIR}/consumer/consumer)
# pkg-config
set(ENV{PKG_CONFIG_PATH} ${prefix}/share/pkgconfig)
execute_process(COMMAND pkg-config --cflags dqkit OUTPUT_VARIABLE cflags RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config does not find dqkit")
endif()
separate_arguments(cflags)
run(${CXX} ${cflags} -DDQKIT_CORE_ONLY ${SOURCE_DIR}/tests/consumer/project/main.cpp -o ${WORK_DIR}/consumer_pc)
run(${WORK_DIR}/consumer_pc)
message(STATUS "consumer builds against the installed package (CMake and pkg-config)")
