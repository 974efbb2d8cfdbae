#!/bin/sh
# The PostgreSQL server CTest's `postgres` fixture shares between the test programs:
#   postgres_server.sh start DIR BINDIR   initdb into DIR, start on a free port, write DIR/port
#   postgres_server.sh stop DIR           immediate shutdown (the data is thrown away), remove DIR
# Test programs find it through BRISANCE_TEST_PG_DIR (tests/server/postgres_fixture.hpp) and make
# a database each; without it they start a server of their own. initdb and postgres refuse root:
# as root (CI) both run as nobody, in a folder nobody owns. Durability is off: tests check the
# store's behaviour, not PostgreSQL's crash safety.
set -eu
command=$1
dir=$2
as_user=""
if [ "$(id -u)" -eq 0 ]; then
  as_user="setpriv --reuid=$(id -u nobody) --regid=$(id -g nobody) --clear-groups --"
fi
case "$command" in
  start)
    bindir=$3
    if [ -f "$dir/data/postmaster.pid" ]; then $as_user "$bindir/pg_ctl" -D "$dir/data" -m immediate stop >/dev/null 2>&1 || true; fi
    rm -rf "$dir"
    mkdir -p "$dir"
    [ -z "$as_user" ] || chown nobody "$dir"
    cd "$dir"
    $as_user "$bindir/initdb" -D "$dir/data" -U brisance --auth=trust --no-sync -E UTF8 \
      --no-instructions >"$dir/initdb.log" 2>&1 || { cat "$dir/initdb.log"; exit 1; }
    for attempt in 1 2 3; do
      port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
      if $as_user "$bindir/pg_ctl" -D "$dir/data" -l "$dir/postgres.log" -w -t 60 -o \
          "-p $port -k $dir -c listen_addresses=127.0.0.1 -c fsync=off -c synchronous_commit=off -c full_page_writes=off -c max_connections=500" \
          start >/dev/null; then
        echo "$port" >"$dir/port"
        echo "$bindir" >"$dir/bindir"
        exit 0
      fi
    done
    cat "$dir/postgres.log"
    exit 1
    ;;
  stop)
    if [ -f "$dir/bindir" ]; then
      $as_user "$(cat "$dir/bindir")/pg_ctl" -D "$dir/data" -m immediate stop >/dev/null
    fi
    rm -rf "$dir"
    ;;
  *)
    echo "usage: $0 start DIR BINDIR | stop DIR" >&2
    exit 2
    ;;
esac
