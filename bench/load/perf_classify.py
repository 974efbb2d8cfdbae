#!/usr/bin/env python3
# Buckets a perf profile of `brisance serve` by component (SQLite, JSON, Beast, kernel TCP, ...),
# separately for the HTTP I/O threads (threads whose stacks show HttpServer) by request handler,
# and for the other threads (workers). Used for bench/results/load.txt:
#   perf record -F 999 --call-graph dwarf,16384 -p SERVER_PID -o p.data -- sleep 5
#   perf script -i p.data -F tid,ip,sym,dso > p.txt
#   python3 bench/load/perf_classify.py p.txt
# A sample goes to the first rule (in order) that matches any frame of its stack.
import sys, re, collections
samples = []
cur = None
for line in open(sys.argv[1], errors='replace'):
    if not line.strip():
        if cur: samples.append(cur)
        cur = None
        continue
    if not line.startswith((' ', '\t')):
        m = re.match(r'\s*(\d+)', line)
        cur = {'tid': int(m.group(1)) if m else 0, 'frames': []}
        continue
    if cur is not None:
        parts = line.strip().split(None, 1)
        if len(parts) == 2:
            cur['frames'].append(parts[1])
if cur: samples.append(cur)

io_tids = set()
for s in samples:
    if any('HttpServer' in f for f in s['frames']): io_tids.add(s['tid'])
tid_count = collections.Counter(s['tid'] for s in samples)
print('samples per thread:', dict(tid_count), ' io threads:', sorted(io_tids))

# Rules: (component, regex) checked from the outermost (caller) frame inward; the innermost
# match wins so e.g. JSON inside submit counts as JSON, SQLite inside get_job as SQLite.
rules = [
    ('worker: simulation', r'engine::simulate|brisance::blast::|brisance::dynamics'),
    ('SQLite COMMIT (WAL write)', r'sqlite3WalFrames|sqlite3PagerCommitPhaseOne|sqlite3BtreeCommitPhaseOne|pagerWalFrames|sqlite3WalCheckpoint|fsync|fdatasync'),
    ('SQLite statements', r'libsqlite3|sqlite3_'),
    ('kernel: TCP send', r'sendmsg|__sys_sendmsg|tcp_sendmsg|__libc_send|writev'),
    ('kernel: TCP recv', r'recvmsg|tcp_recvmsg|__libc_recv|readv'),
    ('kernel: futex/lock/wakeup', r'futex|__lll_lock|pthread_cond|pthread_mutex|finish_task_switch|try_to_wake_up|^schedule '),
    ('kernel: epoll', r'epoll_wait|ep_poll|do_epoll'),
    ('scene validation (parse_scene)', r'parse_scene'),
    ('JSON parse', r'nlohmann.*(parser|lexer|from_json)|json::parse'),
    ('JSON build/dump (job_to_json, iso_time)', r'nlohmann|job_to_json|iso_time|gmtime|__tz|snprintf|vfprintf|__printf'),
    ('metrics', r'Metrics::'),
    ('logging', r'log_event'),
    ('Beast HTTP parse/serialize', r'beast::http::'),
    ('job id / request id', r'new_job_id|request_id_for|mt19937|random_device'),
    ('Asio scheduler/timers', r'boost::asio::detail'),
]
def classify(frames):
    for comp, rx in rules:
        for f in frames:
            if re.search(rx, f):
                return comp
    return 'other (malloc, memcpy, std::string, ...)'

def handler(frames):
    j=' '.join(frames)
    if re.search(r'JobService::submit|create_job', j): return 'io: POST /v1/jobs handler'
    if re.search(r'JobService::job|get_job', j): return 'io: GET /v1/jobs/{id} handler'
    if re.search(r'queue_counts', j): return 'io: GET /v1/queue handler'
    return 'io: transport (outside Api::handle)' if 'Api::handle' not in j else 'io: Api other'
groups = collections.defaultdict(collections.Counter)
for s in samples:
    grp = 'io (all)' if s['tid'] in io_tids else 'other threads'
    if s['tid'] in io_tids:
        groups[handler(s['frames'])][classify(s['frames'])] += 1
    groups[grp][classify(s['frames'])] += 1
for grp, c in groups.items():
    total = sum(c.values())
    print(f'\n== {grp}: {total} samples')
    for comp, n in c.most_common():
        print(f'  {100*n/total:5.1f}%  {n:6d}  {comp}')
