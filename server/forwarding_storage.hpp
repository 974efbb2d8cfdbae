// server/forwarding_storage: a Storage that hands every call to another one, for decorators that
// change a few calls (server/blob_store's results in files; tests that watch a call).
#pragma once

#include <memory>
#include <utility>

#include "server/storage.hpp"

namespace brisance::server {

class ForwardingStorage : public Storage {
 public:
  explicit ForwardingStorage(std::unique_ptr<Storage> inner) : inner_(std::move(inner)) {}

  CreateResult create_job(const NewJob& job) override { return inner_->create_job(job); }
  std::optional<JobRecord> get_job(std::string_view id) override { return inner_->get_job(id); }
  JobPage list_jobs(const JobFilter& filter, std::int64_t before_seq, int limit) override {
    return inner_->list_jobs(filter, before_seq, limit);
  }
  std::int64_t count_queued() override { return inner_->count_queued(); }
  QueueCounts queue_counts(std::int64_t now_ms) override { return inner_->queue_counts(now_ms); }
  std::optional<ClaimedJob> claim_next(std::string_view owner, std::int64_t now_ms,
                                       std::int64_t lease_ms) override {
    return inner_->claim_next(owner, now_ms, lease_ms);
  }
  bool renew_lease(std::string_view id, std::string_view owner, std::int64_t until_ms) override {
    return inner_->renew_lease(id, owner, until_ms);
  }
  bool set_progress(std::string_view id, std::string_view owner, double progress,
                    std::int64_t now_ms) override {
    return inner_->set_progress(id, owner, progress, now_ms);
  }
  bool fail(std::string_view id, std::string_view owner, std::string_view error_type,
            std::string_view message, std::int64_t now_ms) override {
    return inner_->fail(id, owner, error_type, message, now_ms);
  }
  bool finish_cancelled(std::string_view id, std::string_view owner, std::int64_t now_ms) override {
    return inner_->finish_cancelled(id, owner, now_ms);
  }
  bool release(std::string_view id, std::string_view owner, std::int64_t now_ms) override {
    return inner_->release(id, owner, now_ms);
  }
  bool cancel_requested(std::string_view id) override { return inner_->cancel_requested(id); }
  CancelOutcome request_cancel(std::string_view id, std::int64_t now_ms) override {
    return inner_->request_cancel(id, now_ms);
  }
  bool delete_job(std::string_view id) override { return inner_->delete_job(id); }
  std::optional<std::string> scene(std::string_view id) override { return inner_->scene(id); }
  std::optional<std::string> result_summary(std::string_view id) override {
    return inner_->result_summary(id);
  }
  PutAsset put_asset(const AssetRecord& asset, std::string_view bytes) override {
    return inner_->put_asset(asset, bytes);
  }
  std::optional<AssetRecord> get_asset(std::string_view id,
                                       std::optional<std::string_view> owner) override {
    return inner_->get_asset(id, owner);
  }
  std::optional<std::string> asset_bytes(std::string_view id,
                                         std::optional<std::string_view> owner) override {
    return inner_->asset_bytes(id, owner);
  }
  RecoveryReport recover_expired(std::int64_t now_ms, int max_attempts) override {
    return inner_->recover_expired(now_ms, max_attempts);
  }
  std::vector<std::string> running_owners() override { return inner_->running_owners(); }
  std::int64_t expire_leases(std::string_view owner) override {
    return inner_->expire_leases(owner);
  }
  std::int64_t prune_finished(std::int64_t before_ms) override {
    return inner_->prune_finished(before_ms);
  }
  bool ping() override { return inner_->ping(); }
  std::optional<std::string> result_blob(std::string_view id) override {
    return inner_->result_blob(id);
  }
  std::vector<std::string> blob_references() override { return inner_->blob_references(); }
  std::optional<JobRecord> claim_callback(std::int64_t now_ms, std::int64_t lease_ms) override {
    return inner_->claim_callback(now_ms, lease_ms);
  }
  bool record_callback(std::string_view id, std::string_view deliveries_json,
                       std::string_view state, std::int64_t next_ms, std::int64_t now_ms) override {
    return inner_->record_callback(id, deliveries_json, state, next_ms, now_ms);
  }
  void watch(JobChanged job_changed, WorkQueued work_queued) override {
    inner_->watch(std::move(job_changed), std::move(work_queued));
  }

  bool complete(std::string_view id, std::string_view owner, const StoredResult& result,
                std::int64_t now_ms) override {
    return inner_->complete(id, owner, result, now_ms);
  }
  std::vector<StoredBody> result_bodies(std::string_view id) override {
    return inner_->result_bodies(id);
  }
  std::vector<StoredFrame> result_frames(std::string_view id, std::int64_t from,
                                         std::int64_t to) override {
    return inner_->result_frames(id, from, to);
  }
  std::optional<std::string> result_encoded(std::string_view id) override {
    return inner_->result_encoded(id);
  }
  std::int64_t collect_blobs(std::int64_t now_ms) override { return inner_->collect_blobs(now_ms); }

 protected:
  std::unique_ptr<Storage> inner_;
};

}  // namespace brisance::server
