-- 003: a job may carry a name and labels given at submission; labels are a flat JSON object of
-- strings, filtered with json_extract (GET /v1/jobs?label=key=value).
ALTER TABLE jobs ADD COLUMN name TEXT NOT NULL DEFAULT '';
ALTER TABLE jobs ADD COLUMN labels TEXT NOT NULL DEFAULT '{}';
