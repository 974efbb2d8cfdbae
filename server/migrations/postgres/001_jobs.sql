-- 001: the job queue and its results (PostgreSQL; the same tables as ../001_jobs.sql).
CREATE TABLE jobs (
  seq BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  id TEXT NOT NULL UNIQUE,
  status TEXT NOT NULL
    CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'cancelled')),
  priority INTEGER NOT NULL DEFAULT 0,
  scene TEXT NOT NULL,
  progress DOUBLE PRECISION NOT NULL DEFAULT 0,
  version BIGINT NOT NULL DEFAULT 1,
  attempts INTEGER NOT NULL DEFAULT 0,
  cancel_requested BOOLEAN NOT NULL DEFAULT false,
  lease_owner TEXT,
  lease_expires_ms BIGINT,
  created_ms BIGINT NOT NULL,
  updated_ms BIGINT NOT NULL,
  started_ms BIGINT,
  finished_ms BIGINT,
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
  job_seq BIGINT NOT NULL REFERENCES jobs (seq) ON DELETE CASCADE,
  body_index INTEGER NOT NULL,
  name TEXT NOT NULL,
  mass_kg DOUBLE PRECISION NOT NULL,
  animated BOOLEAN NOT NULL,
  initial_pose BYTEA NOT NULL,  -- 7 float64: x y z qx qy qz qw
  vertices BYTEA NOT NULL,      -- float32 x y z per vertex
  triangles BYTEA NOT NULL,     -- uint32 a b c per triangle
  PRIMARY KEY (job_seq, body_index)
);

-- One row per frame: float32 x y z qx qy qz qw per animated body, in body order.
CREATE TABLE job_frames (
  job_seq BIGINT NOT NULL REFERENCES jobs (seq) ON DELETE CASCADE,
  frame INTEGER NOT NULL,
  time_s DOUBLE PRECISION NOT NULL,
  poses BYTEA NOT NULL,
  PRIMARY KEY (job_seq, frame)
);
