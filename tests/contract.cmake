# The HTTP API contract, api/openapi.yaml; included from tests/CMakeLists.txt.
#   contract.lint  Redocly lints the spec (tests/contract/lint.mjs, rules in
#                  tests/contract/redocly.yaml): any error or warning fails.
#   contract.api   tests/contract/contract.mjs starts real `brisance serve` processes, drives every
#                  endpoint and every status code it can provoke, and validates each response
#                  (status, Content-Type, headers, body; the binary frame layout) against the spec.
# Their npm packages (@redocly/cli, ajv, ajv-formats, yaml) are pinned in
# tests/contract/package-lock.json and installed by `npm ci --prefix tests/contract`; whether they
# are installed is checked when the tests run (each script exits 2 naming the fix), so installing
# them after configuring needs no re-run of CMake. Without node on PATH both tests fail.
set(BRISANCE_CONTRACT_DIR ${CMAKE_CURRENT_LIST_DIR}/contract)
find_program(BRISANCE_NODE_EXECUTABLE node)

if(BRISANCE_NODE_EXECUTABLE)
  if(NOT EXISTS ${BRISANCE_CONTRACT_DIR}/node_modules/@redocly/cli
     OR NOT EXISTS ${BRISANCE_CONTRACT_DIR}/node_modules/ajv)
    message(WARNING "contract.lint and contract.api will fail until their packages are installed: "
                    "run `npm ci --prefix tests/contract` from the repository root.")
  endif()
  add_test(NAME contract.lint
           COMMAND ${BRISANCE_NODE_EXECUTABLE} ${BRISANCE_CONTRACT_DIR}/lint.mjs
                   ${PROJECT_SOURCE_DIR}/api/openapi.yaml
           WORKING_DIRECTORY ${BRISANCE_CONTRACT_DIR})
  set_tests_properties(contract.lint PROPERTIES TIMEOUT 120)
  add_test(NAME contract.api
           COMMAND ${BRISANCE_NODE_EXECUTABLE} ${BRISANCE_CONTRACT_DIR}/contract.mjs
                   $<TARGET_FILE:brisance>
           WORKING_DIRECTORY ${BRISANCE_CONTRACT_DIR})
  # The script gives up by itself after 240 s; it starts three servers of one worker each.
  set_tests_properties(contract.api PROPERTIES TIMEOUT 300 PROCESSORS 2)
else()
  # CI must run the contract: a missing node is a failure, as for the glTF validator (io.cmake).
  message(WARNING "contract.lint and contract.api will fail: node was not found on PATH. "
                  "Install the Debian packages nodejs and npm (make gltf-validator does), run "
                  "`npm ci --prefix tests/contract`, then re-run CMake.")
  foreach(name contract.lint contract.api)
    add_test(NAME ${name} COMMAND sh -c "echo '${name}: node was not found on PATH' >&2; exit 1")
  endforeach()
endif()
