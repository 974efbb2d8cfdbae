// server/routes: the API's handlers, one file per resource — jobs (submit, list, get, delete,
// cancel, scene), results (summary, frames, meshes, glb), assets (upload, get), blast (the
// calculator and the explosives), response (an element's SDOF response and P–I curve), meta
// (probes, metrics, the contract, the queue, the dashboard's files). Each handler is a function
// from a matched request to a response; server/api.cpp holds the route table that picks one, and
// the authentication in front of it.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "server/api.hpp"
#include "server/http_util.hpp"
#include "server/problem.hpp"

namespace brisance::server::routes {

// What a handler may use: the request, its parsed target, the {id} segment of the route (if it
// has one), the long-poll state of a request being retried, and the service behind the API.
struct Context {
  const HttpRequest& request;
  const Target& target;
  std::string id;
  const std::optional<LongPoll>& poll;
  JobService& service;
  Metrics& metrics;
  const std::function<WorkerGauges()>& workers;
  const ApiOptions& options;
  // The caller's key; nullopt when the server runs without keys.
  std::optional<ApiKey> key;

  WorkerGauges worker_gauges() const { return workers ? workers() : WorkerGauges{}; }
  // Whose jobs the caller sees: its own, or everyone's (no keys, or an admin key).
  std::optional<std::string_view> owner_filter() const {
    if (!key || key->scope == Scope::admin) return std::nullopt;
    return std::string_view(key->name);
  }
  // The job {id} if it exists and the caller may see it; a job of another key is not found.
  std::optional<JobRecord> visible_job() const {
    auto job = service.job(id);
    if (job && owner_filter() && job->owner != *owner_filter()) return std::nullopt;
    return job;
  }
};

using Handler = HttpResponse (*)(const Context&);

// Job JSON and its ETag (also part of results and cancel answers).
std::string job_json(const JobRecord& job);
std::string job_etag(const JobRecord& job);
std::string job_path(std::string_view id);

// jobs.cpp
HttpResponse submit_job(const Context& c);
HttpResponse list_jobs(const Context& c);
HttpResponse get_job(const Context& c);
HttpResponse delete_job(const Context& c);
HttpResponse cancel_job(const Context& c);
HttpResponse job_scene(const Context& c);
// results.cpp
HttpResponse job_result(const Context& c);
HttpResponse job_frames(const Context& c);
HttpResponse job_meshes(const Context& c);
HttpResponse job_glb(const Context& c);
// assets.cpp
HttpResponse upload_asset(const Context& c);
HttpResponse get_asset(const Context& c);
// blast.cpp
HttpResponse blast_calculator(const Context& c);
HttpResponse explosives(const Context& c);
// response.cpp
HttpResponse element_response(const Context& c);
HttpResponse pressure_impulse(const Context& c);
// meta.cpp
HttpResponse healthz(const Context& c);
HttpResponse readyz(const Context& c);
HttpResponse metrics(const Context& c);
HttpResponse openapi(const Context& c);
HttpResponse queue(const Context& c);
// The dashboard's static files, for any GET outside the API; nullopt when there is no such file.
std::optional<HttpResponse> static_file(const Context& c);

}  // namespace brisance::server::routes
