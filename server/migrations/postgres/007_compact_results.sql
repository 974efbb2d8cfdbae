-- 007: a result's meshes and frames as one compact byte string (server/compact_result: zstd, frames
-- in chunks of delta-coded poses), one row per job, instead of job_bodies and job_frames rows.
-- Results stored before keep their rows and read as before; a job has one or the other (or
-- jobs.result_blob, when the bytes are in the blob store).
CREATE TABLE job_results (
  job_seq BIGINT PRIMARY KEY REFERENCES jobs (seq) ON DELETE CASCADE,
  data BYTEA NOT NULL
);
