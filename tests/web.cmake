# The dashboard (web/) and the TypeScript client (clients/typescript); included from
# tests/CMakeLists.txt.
#   web.typecheck  tests/web/typecheck.mjs: clients/typescript/src/schema.d.ts is what
#                  openapi-typescript makes of api/openapi.yaml today, and tsc (strict) accepts
#                  clients/typescript and web/.
#   web.browser    tests/web/dashboard.mjs: playwright-core drives Debian's chromium (headless,
#                  WebGL on SwiftShader) against real `brisance serve` processes serving web/dist:
#                  a job submitted from the form runs to done, the 3D player draws, the queue
#                  polls with ETags, the blast plots, API keys. Screenshots go to
#                  ${CMAKE_BINARY_DIR}/artifacts/web.
# Their packages are pinned in the package-lock.json files of clients/typescript, web and
# tests/web (`make web` and `make test` install them and build web/dist; chromium is the Debian
# package). Whether they are there is checked when the tests run (each script exits 2 naming
# the fix), so installing them after configuring needs no re-run of CMake.
set(BRISANCE_WEB_TESTS_DIR ${CMAKE_CURRENT_LIST_DIR}/web)
find_program(BRISANCE_NODE_EXECUTABLE node)

if(BRISANCE_NODE_EXECUTABLE)
  if(NOT EXISTS ${PROJECT_SOURCE_DIR}/web/node_modules/typescript
     OR NOT EXISTS ${PROJECT_SOURCE_DIR}/clients/typescript/node_modules/openapi-typescript
     OR NOT EXISTS ${BRISANCE_WEB_TESTS_DIR}/node_modules/playwright-core)
    message(WARNING "web.typecheck and web.browser will fail until their packages are installed "
                    "and web/dist is built: run `make web` and "
                    "`npm ci --prefix tests/web` from the repository root.")
  endif()
  add_test(NAME web.typecheck
           COMMAND ${BRISANCE_NODE_EXECUTABLE} ${BRISANCE_WEB_TESTS_DIR}/typecheck.mjs
                   ${PROJECT_SOURCE_DIR}
           WORKING_DIRECTORY ${BRISANCE_WEB_TESTS_DIR})
  set_tests_properties(web.typecheck PROPERTIES TIMEOUT 180)
  add_test(NAME web.browser
           COMMAND ${BRISANCE_NODE_EXECUTABLE} ${BRISANCE_WEB_TESTS_DIR}/dashboard.mjs
                   $<TARGET_FILE:brisance> ${PROJECT_SOURCE_DIR}/web/dist
                   ${CMAKE_BINARY_DIR}/artifacts/web
           WORKING_DIRECTORY ${BRISANCE_WEB_TESTS_DIR})
  # The script gives up by itself after 270 s; chromium and the server's worker share the cores.
  set_tests_properties(web.browser PROPERTIES TIMEOUT 300 PROCESSORS 2)
else()
  # CI must run these: a missing node is a failure, as for the contract tests (contract.cmake).
  message(WARNING "web.typecheck and web.browser will fail: node was not found on PATH. "
                  "Install the Debian packages nodejs and npm (make gltf-validator does), run "
                  "`make web`, then re-run CMake.")
  foreach(name web.typecheck web.browser)
    add_test(NAME ${name} COMMAND sh -c "echo '${name}: node was not found on PATH' >&2; exit 1")
  endforeach()
endif()
