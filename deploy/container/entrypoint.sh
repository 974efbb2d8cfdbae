#!/bin/sh
# Entry point of the Brisance image (deploy/container/Dockerfile).
#   (no arguments)          brisance serve, configured by the BRISANCE_* variables
#   --workers 4 ...         brisance serve --workers 4 ...
#   api-key --name ci ...   any other brisance command
#   sh                      any other program
# Before serving it checks that the data folder is writable, so that a volume mounted with the
# wrong owner says so in one line instead of as an SQLite error. It execs, so brisance is PID 1
# and gets the SIGTERM of `docker stop` or Kubernetes itself (it waits for it with sigwait, which
# works for PID 1: a blocked signal is queued, not dropped).
set -eu

if [ "$#" -eq 0 ]; then
  set -- serve
fi
case "$1" in
  -*) set -- serve "$@" ;;
esac

if [ "$1" = serve ]; then
  data="${BRISANCE_DATA:-data}"
  previous=""
  for argument in "$@"; do
    case "$argument" in
      --data=*) data="${argument#--data=}" ;;
    esac
    if [ "$previous" = --data ]; then
      data="$argument"
    fi
    previous="$argument"
  done
  mkdir -p "$data" 2>/dev/null || true
  if [ ! -d "$data" ] || [ ! -w "$data" ]; then
    echo "brisance-entrypoint: the data folder $data is not a folder that user $(id -u):$(id -g)" \
      "can write: mount a volume there owned by that user (docs/deploy.md \"Containers\")" >&2
    exit 1
  fi
fi

case "$1" in
  serve | run | blast | fracture | validate | api-key | version | --version | help | --help)
    exec brisance "$@"
    ;;
esac
exec "$@"
