#!/bin/bash
# The image's HEALTHCHECK: exit 0 when GET PATH (default /healthz; compose uses /readyz) on this
# container's port answers 200. Bash's /dev/tcp does the request, so the image needs no curl.
set -u
path="${1:-/healthz}"
port="${BRISANCE_PORT:-8080}"
exec 3<>"/dev/tcp/127.0.0.1/${port}" || exit 1
printf 'GET %s HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n' "$path" >&3
IFS= read -r -t 2 status <&3 || exit 1
case "$status" in
  "HTTP/1.1 200"*) exit 0 ;;
esac
echo "brisance-healthcheck: ${path} answered: ${status%$'\r'}" >&2
exit 1
