#!/bin/sh
# The load bench on the PostgreSQL store with 1 and with 3 nodes (issue 14):
#   bench/load/postgres_bench.sh BUILD_DIR [load_bench flags…]
# starts a PostgreSQL server of its own in a temporary folder (Debian's postgresql package, the
# newest installed version, durable: fsync and synchronous_commit on, as a production server;
# listen on 127.0.0.1, max_connections 300), makes one database per run, runs
#   load_bench --server BUILD_DIR/cli/brisance --store URL --nodes N [flags]
# for N = 1 and N = 3, and stops the server. initdb and postgres refuse root: as root they run as
# nobody (as tests/server/postgres_server.sh does).
set -eu
build=${1:?usage: postgres_bench.sh BUILD_DIR [load_bench flags...]}
shift
bindir=$(ls -d /usr/lib/postgresql/*/bin | sort -V | tail -n 1)
dir=$(mktemp -d /tmp/brisance-pg-bench-XXXXXX)
as_user=""
if [ "$(id -u)" -eq 0 ]; then
  as_user="setpriv --reuid=$(id -u nobody) --regid=$(id -g nobody) --clear-groups --"
  chown nobody "$dir"
fi
cd "$dir"
$as_user "$bindir/initdb" -D "$dir/data" -U brisance --auth=trust -E UTF8 --no-instructions \
  >"$dir/initdb.log" 2>&1 || { cat "$dir/initdb.log"; exit 1; }
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
$as_user "$bindir/pg_ctl" -D "$dir/data" -l "$dir/postgres.log" -w -t 60 -o \
  "-p $port -k $dir -c listen_addresses=127.0.0.1 -c max_connections=300" start >/dev/null
trap '$as_user "$bindir/pg_ctl" -D "$dir/data" -m fast stop >/dev/null; cd /; rm -rf "$dir"' EXIT
cd - >/dev/null
echo "PostgreSQL: $("$bindir/postgres" --version), port $port;" \
  "fsync $("$bindir/psql" -h 127.0.0.1 -p "$port" -U brisance -d postgres -Atc 'SHOW fsync')," \
  "synchronous_commit $("$bindir/psql" -h 127.0.0.1 -p "$port" -U brisance -d postgres -Atc 'SHOW synchronous_commit')"
status=0
for nodes in 1 3; do
  "$bindir/psql" -h 127.0.0.1 -p "$port" -U brisance -d postgres -qc "CREATE DATABASE bench$nodes"
  echo
  echo "================================================================================================"
  echo "\$ load_bench --server $build/cli/brisance --store postgres://brisance@127.0.0.1:$port/bench$nodes --nodes $nodes $*"
  echo "(load average before: $(cut -d' ' -f1-3 /proc/loadavg))"
  "$build/bench/load_bench" --server "$build/cli/brisance" \
    --store "postgres://brisance@127.0.0.1:$port/bench$nodes" --nodes "$nodes" "$@" || status=1
done
exit $status
