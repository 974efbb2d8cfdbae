# deploy/ checked without a container runtime or a running systemd; include(deploy.cmake) from
# tests/CMakeLists.txt, after clients.cmake (whose Python it uses).
#   deploy.manifests  tests/deploy/manifests.mjs: the Kubernetes objects against the API schemas
#                     and for unknown fields, compose.yaml against the Compose spec, and what the
#                     files must agree on (npm packages pinned in tests/deploy/package-lock.json,
#                     installed by `npm ci --prefix tests/deploy`, as `make test` does).
#   deploy.systemd    systemd-analyze verify and security on the unit (Debian package systemd).
#   deploy.sandbox    the unit's ExecStart traced with strace through probes, a job and SIGTERM:
#                     its system calls, sockets, writes and /proc reads against the unit's sandbox.
#   deploy.dockerfile the image's stages, its runtime packages against the binary's libraries.
#   deploy.run        each form's command line and settings run against the built binary.
set(BRISANCE_DEPLOY_TEST_DIR ${CMAKE_CURRENT_LIST_DIR}/deploy)

if(BRISANCE_NODE_EXECUTABLE)
  if(NOT EXISTS ${BRISANCE_DEPLOY_TEST_DIR}/node_modules/kubernetes-models)
    message(WARNING "deploy.manifests will fail until its packages are installed: run "
                    "`npm ci --prefix tests/deploy` (or make deploy-test-deps).")
  endif()
  add_test(NAME deploy.manifests
           COMMAND ${BRISANCE_NODE_EXECUTABLE} ${BRISANCE_DEPLOY_TEST_DIR}/manifests.mjs
                   ${PROJECT_SOURCE_DIR}
           WORKING_DIRECTORY ${BRISANCE_DEPLOY_TEST_DIR})
  set_tests_properties(deploy.manifests PROPERTIES TIMEOUT 120)
else()
  add_test(NAME deploy.manifests
           COMMAND sh -c "echo 'deploy.manifests: node was not found on PATH' >&2; exit 1")
endif()

set(_deploy_classes systemd SystemdUnit sandbox SystemdSandbox dockerfile Dockerfile run RunForms)
while(_deploy_classes)
  list(POP_FRONT _deploy_classes _name _class)
  if(BRISANCE_CLIENT_PYTHON)
    add_test(NAME deploy.${_name}
             COMMAND ${BRISANCE_CLIENT_PYTHON} ${BRISANCE_DEPLOY_TEST_DIR}/deploy_test.py -v ${_class}
             WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    set_tests_properties(deploy.${_name} PROPERTIES
      ENVIRONMENT "BRISANCE_BINARY=$<TARGET_FILE:brisance>"
      TIMEOUT 300)
  else()
    add_test(NAME deploy.${_name}
             COMMAND sh -c "echo 'deploy.${_name}: no Python 3 interpreter was found' >&2; exit 1")
  endif()
endwhile()
# The forms run servers of one worker per core: keep them off the other CPU-heavy tests.
if(BRISANCE_CLIENT_PYTHON)
  set_tests_properties(deploy.run PROPERTIES PROCESSORS 2)
endif()
