// server/metrics: counters and histograms for `/metrics` in the Prometheus text format (0.0.4):
// requests by route, method and status, request latency per route, jobs finished by outcome and
// their run time, plus the queue gauges read at scrape time.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "server/storage.hpp"

namespace brisance::server {

class Histogram {
 public:
  explicit Histogram(std::vector<double> upper_bounds);
  void observe(double value);
  // Appends the _bucket, _sum and _count lines; `labels` is empty or `a="b",` (trailing comma).
  void render(std::string& out, std::string_view name, std::string_view labels) const;

 private:
  std::vector<double> bounds_;
  std::vector<std::uint64_t> counts_;  // per bucket, not cumulative; last is +Inf
  double sum_ = 0.0;
  std::uint64_t count_ = 0;
};

struct WorkerGauges {
  int busy = 0;
  int total = 0;
};

class Metrics {
 public:
  Metrics();
  void record_request(std::string_view route, std::string_view method, int status, double seconds);
  void record_job(JobStatus outcome, double run_seconds);
  std::string render(const QueueCounts& queue, const WorkerGauges& workers,
                     const StoredResultTotals& stored = {}) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::tuple<std::string, std::string, int>, std::uint64_t> requests_;
  std::map<std::string, Histogram, std::less<>> latency_;
  std::array<std::uint64_t, 5> jobs_finished_{};
  Histogram job_run_time_;
};

}  // namespace brisance::server
