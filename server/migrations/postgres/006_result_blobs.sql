-- 006: a result's bodies and frames may live in the blob store (serve --blobs DIR,
-- server/blob_store) instead of job_bodies and job_frames: result_blob is then the SHA-256 of
-- the blob file, NULL when the result is in the database. The index serves the blob collector's
-- "which digests are still named" query.
ALTER TABLE jobs ADD COLUMN result_blob TEXT;
CREATE INDEX jobs_result_blob ON jobs (result_blob) WHERE result_blob IS NOT NULL;
