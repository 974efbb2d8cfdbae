# The API clients (clients/); include(clients.cmake) from tests/CMakeLists.txt.
#   clients.python  clients/python/tests (unittest, standard library only) start their own
#                   `brisance serve` processes from $BRISANCE_BINARY and drive brisance_client and
#                   its command line against them.
#   docs.pipelines  every shell and Python block of docs/pipelines.md, in order, against a real
#                   `brisance serve` (tests/docs/run_doc_blocks.py; needs curl and jq, from
#                   `make web-test-deps`); blocks marked <!-- not run: ... --> are listed as skipped.
# Debian's /usr/bin/python3 is preferred: on developer machines the python3 on PATH is often a
# pyenv shim whose interpreter depends on the working directory. Any Python >= 3.8 works.
if(EXISTS /usr/bin/python3)
  set(BRISANCE_CLIENT_PYTHON /usr/bin/python3)
else()
  find_package(Python3 3.8 COMPONENTS Interpreter)
  if(Python3_Interpreter_FOUND)
    set(BRISANCE_CLIENT_PYTHON ${Python3_EXECUTABLE})
  endif()
endif()

if(BRISANCE_CLIENT_PYTHON)
  add_test(NAME clients.python
           COMMAND ${BRISANCE_CLIENT_PYTHON} -m unittest discover -s clients/python/tests -v
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(clients.python PROPERTIES
    ENVIRONMENT "BRISANCE_BINARY=$<TARGET_FILE:brisance>;PYTHONPATH=${PROJECT_SOURCE_DIR}/clients/python"
    # About 25 s; the test servers run one worker each, one at a time.
    TIMEOUT 180
    PROCESSORS 2)
  add_test(NAME docs.pipelines
           COMMAND ${BRISANCE_CLIENT_PYTHON} tests/docs/run_doc_blocks.py
                   --brisance $<TARGET_FILE:brisance> --doc docs/pipelines.md
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(docs.pipelines PROPERTIES TIMEOUT 300 PROCESSORS 2)
else()
  # CI must run the client tests: a missing Python is a failure, not a skip.
  message(WARNING "clients.python will fail: no Python 3 interpreter was found.")
  add_test(NAME clients.python
           COMMAND sh -c "echo 'clients.python: no Python 3 interpreter was found' >&2; exit 1")
endif()
