# Installs the built tree into a scratch prefix, then configures, builds and runs a tiny outside
# project against it: the check that find_package(rattle) and rattle::engine work for users.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix
  RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/build
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_EXPORT_COMPILE_COMMANDS=ON
    "-DCMAKE_CXX_FLAGS=${CONSUMER_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_FLAGS}"
  RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "configuring the consumer against the installed package failed: ${rc}")
endif()
# Linking rattle::engine compiles the consumer's own sources without contraction (README, where it shows
# find_package(rattle)): the installed target carries the flag.
file(READ ${WORK_DIR}/build/compile_commands.json commands)
if(NOT commands MATCHES "main\\.cpp" OR NOT commands MATCHES "-ffp-contract=off")
  message(FATAL_ERROR "the consumer's main.cpp is not compiled with -ffp-contract=off: ${commands}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the consumer failed: ${rc}")
endif()
execute_process(COMMAND ${WORK_DIR}/build/consumer RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "contacts: 1")
  message(FATAL_ERROR "the consumer ran wrong (exit ${rc}): ${out}")
endif()
message(STATUS "consumer: ${out}")
