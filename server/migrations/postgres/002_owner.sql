-- 002: every job belongs to the API key that submitted it ('' when the server runs without keys).
-- Idempotency keys are scoped to their owner: the stored key is prefixed with the owner's name.
ALTER TABLE jobs ADD COLUMN owner TEXT NOT NULL DEFAULT '';
CREATE INDEX jobs_owner_seq ON jobs (owner, seq);
