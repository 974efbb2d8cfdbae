-- 001: the job queue and its results.
CREATE TABLE jobs (
  seq INTEGER PRIMARY KEY AUTOINCREMENT,
  id TEXT NOT NULL UNIQUE,
  status TEXT NOT NULL
    CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'cancelled')),
  priority INTEGER NOT NULL DEFAULT 0,
  scene TEXT NOT NULL,
  progress REAL NOT NULL DEFAULT 0,
  version INTEGER NOT NULL DEFAULT 1,
  attempts INTEGER NOT NULL DEFAULT 0,
  cancel_requested INTEGER NOT NULL DEFAULT 0,
  lease_owner TEXT,
  lease_expires_ms INTEGER,
  created_ms INTEGER NOT NULL,
  updated_ms INTEGER NOT NULL,
  started_ms INTEGER,
  finished_ms INTEGER,
  error_type TEXT,
  error TEXT,
  idempotency_key TEXT UNIQUE,
  request_hash TEXT,
  stats TEXT,
  result_summary TEXT
);
-- The claim order: highest priority first, then oldest.
CREATE INDEX jobs_queue ON jobs (priority DESC, seq) WHERE status = 'queued';
CREATE INDEX jobs_status_seq ON jobs (status, seq);
CREATE INDEX jobs_lease ON jobs (lease_expires_ms) WHERE status = 'running';
CREATE INDEX jobs_finished ON jobs (finished_ms) WHERE finished_ms IS NOT NULL;

-- One row per body of a result: the mesh is stored once, not per frame.
CREATE TABLE job_bodies (
  job_seq INTEGER NOT NULL REFERENCES jobs (seq) ON DELETE CASCADE,
  body_index INTEGER NOT NULL,
  name TEXT NOT NULL,
  mass_kg REAL NOT NULL,
  animated INTEGER NOT NULL,
  initial_pose BLOB NOT NULL,  -- 7 float64: x y z qx qy qz qw
  vertices BLOB NOT NULL,      -- float32 x y z per vertex
  triangles BLOB NOT NULL,     -- uint32 a b c per triangle
  PRIMARY KEY (job_seq, body_index)
) WITHOUT ROWID;

-- One row per frame: float32 x y z qx qy qz qw per animated body, in body order.
CREATE TABLE job_frames (
  job_seq INTEGER NOT NULL REFERENCES jobs (seq) ON DELETE CASCADE,
  frame INTEGER NOT NULL,
  time_s REAL NOT NULL,
  poses BLOB NOT NULL,
  PRIMARY KEY (job_seq, frame)
) WITHOUT ROWID;
