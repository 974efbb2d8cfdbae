#include "server/metrics.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace brisance::server {
namespace {

void append_number(std::string& out, double value) {
  char buffer[32];
  const int n = std::snprintf(buffer, sizeof buffer, "%.9g", value);
  out.append(buffer, static_cast<std::size_t>(n));
}

void append_count(std::string& out, std::uint64_t value) {
  out += std::to_string(value);
}

// Label values are route templates, methods and states: escape the three characters the format
// reserves anyway.
std::string escape_label(std::string_view value) {
  std::string out;
  for (char c : value) {
    if (c == '\\' || c == '"') out.push_back('\\');
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out.push_back(c);
  }
  return out;
}

const std::vector<double> kLatencyBuckets = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1,
                                             0.25,   0.5,   1.0,    2.5,   5.0,  10.0,  30.0};
const std::vector<double> kRunTimeBuckets = {0.01, 0.05, 0.1,  0.25, 0.5,   1.0,   2.5,
                                             5.0,  10.0, 30.0, 60.0, 120.0, 300.0, 600.0};

}  // namespace

Histogram::Histogram(std::vector<double> upper_bounds)
    : bounds_(std::move(upper_bounds)), counts_(bounds_.size() + 1, 0) {}

void Histogram::observe(double value) {
  const auto bucket = static_cast<std::size_t>(
      std::lower_bound(bounds_.begin(), bounds_.end(), value) - bounds_.begin());
  ++counts_[bucket];
  sum_ += value;
  ++count_;
}

void Histogram::render(std::string& out, std::string_view name, std::string_view labels) const {
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i <= bounds_.size(); ++i) {
    cumulative += counts_[i];
    out.append(name).append("_bucket{").append(labels).append("le=\"");
    if (i < bounds_.size()) {
      append_number(out, bounds_[i]);
    } else {
      out += "+Inf";
    }
    out += "\"} ";
    append_count(out, cumulative);
    out += '\n';
  }
  // `a="b",` without its comma, in braces; nothing at all without labels.
  const std::string bare =
      labels.empty() ? std::string() : "{" + std::string(labels.substr(0, labels.size() - 1)) + "}";
  out.append(name).append("_sum").append(bare).append(" ");
  append_number(out, sum_);
  out.append("\n").append(name).append("_count").append(bare).append(" ");
  append_count(out, count_);
  out += '\n';
}

Metrics::Metrics() : job_run_time_(kRunTimeBuckets) {}

void Metrics::record_request(std::string_view route, std::string_view method, int status,
                             double seconds) {
  // Labels come from a closed set (the route table's templates and the methods HTTP defines), so
  // requests with made-up methods cannot grow the metrics without bound.
  static constexpr std::string_view kMethods[] = {"GET",     "HEAD",    "POST",  "PUT",  "DELETE",
                                                  "OPTIONS", "CONNECT", "TRACE", "PATCH"};
  const bool known =
      std::find(std::begin(kMethods), std::end(kMethods), method) != std::end(kMethods);
  std::lock_guard lock(mutex_);
  ++requests_[{std::string(route), known ? std::string(method) : std::string("other"), status}];
  auto it = latency_.find(route);
  if (it == latency_.end())
    it = latency_.emplace(std::string(route), Histogram(kLatencyBuckets)).first;
  it->second.observe(seconds);
}

void Metrics::record_job(JobStatus outcome, double run_seconds) {
  std::lock_guard lock(mutex_);
  ++jobs_finished_[static_cast<std::size_t>(outcome)];
  job_run_time_.observe(run_seconds);
}

std::string Metrics::render(const QueueCounts& queue, const WorkerGauges& workers,
                            const StoredResultTotals& stored) const {
  std::string out;
  out.reserve(8192);
  std::lock_guard lock(mutex_);
  out +=
      "# HELP brisance_http_requests_total HTTP requests answered, by route template, method "
      "and status.\n# TYPE brisance_http_requests_total counter\n";
  for (const auto& [key, count] : requests_) {
    const auto& [route, method, status] = key;
    out += "brisance_http_requests_total{route=\"" + escape_label(route) + "\",method=\"" +
           escape_label(method) + "\",status=\"" + std::to_string(status) + "\"} ";
    append_count(out, count);
    out += '\n';
  }
  out +=
      "# HELP brisance_http_request_duration_seconds Time from a request's last byte read to "
      "its response queued, by route template.\n"
      "# TYPE brisance_http_request_duration_seconds histogram\n";
  for (const auto& [route, histogram] : latency_) {
    histogram.render(out, "brisance_http_request_duration_seconds",
                     "route=\"" + escape_label(route) + "\",");
  }
  out += "# HELP brisance_jobs Jobs in the store, by state.\n# TYPE brisance_jobs gauge\n";
  for (JobStatus s : {JobStatus::queued, JobStatus::running, JobStatus::succeeded,
                      JobStatus::failed, JobStatus::cancelled}) {
    out += "brisance_jobs{state=\"" + std::string(to_string(s)) + "\"} ";
    append_count(out, static_cast<std::uint64_t>(queue.by_status[static_cast<std::size_t>(s)]));
    out += '\n';
  }
  out +=
      "# HELP brisance_jobs_finished_total Jobs this process finished, by outcome.\n"
      "# TYPE brisance_jobs_finished_total counter\n";
  for (JobStatus s : {JobStatus::succeeded, JobStatus::failed, JobStatus::cancelled}) {
    out += "brisance_jobs_finished_total{outcome=\"" + std::string(to_string(s)) + "\"} ";
    append_count(out, jobs_finished_[static_cast<std::size_t>(s)]);
    out += '\n';
  }
  out +=
      "# HELP brisance_job_run_seconds Wall time of job runs in this process.\n"
      "# TYPE brisance_job_run_seconds histogram\n";
  job_run_time_.render(out, "brisance_job_run_seconds", "");
  out += "# HELP brisance_workers Simulation workers, by state.\n# TYPE brisance_workers gauge\n";
  out += "brisance_workers{state=\"busy\"} " + std::to_string(workers.busy) + "\n";
  out += "brisance_workers{state=\"idle\"} " + std::to_string(workers.total - workers.busy) + "\n";
  out +=
      "# HELP brisance_oldest_queued_job_age_seconds Age of the oldest queued job.\n"
      "# TYPE brisance_oldest_queued_job_age_seconds gauge\n";
  out += "brisance_oldest_queued_job_age_seconds ";
  double age_s = 0.0;
  if (queue.oldest_queued_created_ms) {
    const auto now = std::chrono::duration_cast<std::chrono::milliseconds>(
                         std::chrono::system_clock::now().time_since_epoch())
                         .count();
    age_s =
        std::max<double>(0.0, static_cast<double>(now - *queue.oldest_queued_created_ms) / 1000.0);
  }
  append_number(out, age_s);
  out += '\n';
  out +=
      "# HELP brisance_results_stored_total Results this process stored.\n"
      "# TYPE brisance_results_stored_total counter\n"
      "brisance_results_stored_total ";
  append_count(out, stored.results);
  out +=
      "\n# HELP brisance_result_stored_bytes_total Bytes of the results this process stored, "
      "as encoded (meshes once, frames delta-coded and zstd-compressed).\n"
      "# TYPE brisance_result_stored_bytes_total counter\n"
      "brisance_result_stored_bytes_total ";
  append_count(out, stored.bytes);
  out += '\n';
  return out;
}

}  // namespace brisance::server
