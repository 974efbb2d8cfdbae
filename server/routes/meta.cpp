// server/routes/meta: the probes (/healthz, /readyz), /metrics, the contract (/openapi.yaml), the
// queue overview (/v1/queue) and the dashboard's static files.
#include <algorithm>

#include <nlohmann/json.hpp>

#include "server/embedded.hpp"
#include "server/log.hpp"
#include "server/routes/routes.hpp"

namespace brisance::server::routes {

using nlohmann::json;

HttpResponse healthz(const Context&) {
  HttpResponse r;
  r.body = json{{"status", "ok"}}.dump();
  return r;
}

HttpResponse readyz(const Context& c) {
  const bool db = c.service.database_ok();
  const WorkerGauges workers = c.worker_gauges();
  const bool disk_low = c.options.free_space && c.options.free_space->low();
  const bool ready = db && workers.total > 0 && !disk_low;
  HttpResponse r;
  r.status = ready ? 200 : 503;
  r.body = json{{"status", ready ? "ready" : "not ready"},
                {"database", db ? "ok" : "unreachable"},
                {"disk", disk_low ? "low" : "ok"},
                {"workers", workers.total}}
               .dump();
  return r;
}

HttpResponse metrics(const Context& c) {
  HttpResponse r;
  r.content_type = "text/plain; version=0.0.4; charset=utf-8";
  r.body = c.metrics.render(c.service.queue_counts(), c.worker_gauges(),
                            c.service.stored_result_totals());
  return r;
}

HttpResponse openapi(const Context&) {
  HttpResponse r;
  r.content_type = "application/yaml";
  for (const EmbeddedFile& file : embedded_api()) {
    if (file.name == "openapi.yaml") r.body = std::string(file.data);
  }
  return r;
}

HttpResponse queue(const Context& c) {
  const QueueCounts counts = c.service.queue_counts();
  const WorkerGauges workers = c.worker_gauges();
  json by_status = json::object();
  for (JobStatus s : {JobStatus::queued, JobStatus::running, JobStatus::succeeded,
                      JobStatus::failed, JobStatus::cancelled}) {
    by_status[std::string(to_string(s))] = counts.by_status[static_cast<std::size_t>(s)];
  }
  json oldest = nullptr;
  if (counts.oldest_queued_created_ms) {
    oldest =
        json{{"created_at", iso_time_utc(*counts.oldest_queued_created_ms)},
             {"age_s",
              std::max<double>(
                  0.0, static_cast<double>(now_ms() - *counts.oldest_queued_created_ms) / 1000.0)}};
  }
  return etagged(c.request, json{{"counts", by_status},
                                 {"workers",
                                  {{"total", workers.total},
                                   {"busy", workers.busy},
                                   {"idle", workers.total - workers.busy}}},
                                 {"oldest_queued", oldest},
                                 {"throughput_per_min", counts.finished_last_minute}}
                                .dump());
}

std::optional<HttpResponse> static_file(const Context& c) {
  if (!c.options.static_file) return std::nullopt;
  std::string_view path = c.target.path;
  while (!path.empty() && path.front() == '/')
    path.remove_prefix(1);
  if (path.empty()) path = "index.html";
  auto file = c.options.static_file(path);
  if (!file) return std::nullopt;
  HttpResponse r;
  r.content_type = std::string(file->first);
  r.body = std::string(file->second);
  r.headers.emplace_back("Cache-Control", "no-cache");
  return r;
}

}  // namespace brisance::server::routes
