-- 004: uploaded mesh files (POST /v1/assets) that scenes name with {"type": "asset"}. The id is
-- the SHA-256 of the bytes; an asset belongs to the API key that uploaded it ('' without keys),
-- so two keys uploading the same file each own a copy.
CREATE TABLE assets (
  owner TEXT NOT NULL DEFAULT '',
  id TEXT NOT NULL,
  format TEXT NOT NULL,
  size_bytes BIGINT NOT NULL,
  nodes TEXT NOT NULL,
  created_ms BIGINT NOT NULL,
  bytes BYTEA NOT NULL,
  PRIMARY KEY (owner, id)
);
CREATE INDEX assets_id ON assets (id);
