-- 003: a job may carry a name and labels given at submission; labels are a flat JSON object of
-- strings kept as the text the service wrote, filtered through jsonb (GET /v1/jobs?label=k=v).
ALTER TABLE jobs ADD COLUMN name TEXT NOT NULL DEFAULT '';
ALTER TABLE jobs ADD COLUMN labels TEXT NOT NULL DEFAULT '{}';
