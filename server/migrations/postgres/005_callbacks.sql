-- 005: a job may name a URL told when it ends (server/callbacks). callback_state is '' (none),
-- 'pending', 'delivered' or 'failed'; callback_next_ms when a sender may try next (also its
-- claim: a sender holding a delivery moves it forward); callback_deliveries the attempts so far.
ALTER TABLE jobs ADD COLUMN callback_url TEXT NOT NULL DEFAULT '',
  ADD COLUMN callback_state TEXT NOT NULL DEFAULT '',
  ADD COLUMN callback_next_ms BIGINT NOT NULL DEFAULT 0,
  ADD COLUMN callback_deliveries TEXT NOT NULL DEFAULT '[]';
CREATE INDEX jobs_callbacks ON jobs (callback_next_ms) WHERE callback_state = 'pending';
