// server/api: the route table and the checks in front of it — which handler a request reaches,
// which methods each resource accepts (405 with Allow otherwise), which need an API key and which
// a write key — and the mapping of every failure to a problem. The handlers live in
// server/routes/, one file per resource.
#include "server/api.hpp"

#include <array>

#include "server/blob_store.hpp"
#include "server/routes/routes.hpp"

namespace brisance::server {
namespace {

enum class Access {
  open,  // probes: no key needed
  key,   // needs a key when keys are configured (and a write key for methods other than GET)
  read,  // needs a key when keys are configured, of any scope: a POST that only computes
};

struct Route {
  std::string_view method;  // "GET" also answers HEAD; "*" answers every method
  std::string_view path;    // segments; "{id}" matches any one segment
  Access access;
  routes::Handler handler;
};

// Every resource of the API (api/openapi.yaml), in the order their methods are listed in Allow.
constexpr std::array kRoutes = {
    // The probes answer every method as they answer GET (api/openapi.yaml).
    Route{"*", "/healthz", Access::open, routes::healthz},
    Route{"*", "/readyz", Access::open, routes::readyz},
    Route{"GET", "/metrics", Access::key, routes::metrics},
    Route{"GET", "/openapi.yaml", Access::key, routes::openapi},
    Route{"GET", "/v1/queue", Access::key, routes::queue},
    Route{"GET", "/v1/explosives", Access::key, routes::explosives},
    Route{"GET", "/v1/blast", Access::key, routes::blast_calculator},
    Route{"POST", "/v1/response", Access::read, routes::element_response},
    Route{"POST", "/v1/pi", Access::read, routes::pressure_impulse},
    Route{"GET", "/v1/jobs", Access::key, routes::list_jobs},
    Route{"POST", "/v1/jobs", Access::key, routes::submit_job},
    Route{"GET", "/v1/jobs/{id}", Access::key, routes::get_job},
    Route{"DELETE", "/v1/jobs/{id}", Access::key, routes::delete_job},
    Route{"POST", "/v1/jobs/{id}/cancel", Access::key, routes::cancel_job},
    Route{"GET", "/v1/jobs/{id}/scene", Access::key, routes::job_scene},
    Route{"GET", "/v1/jobs/{id}/result", Access::key, routes::job_result},
    Route{"GET", "/v1/jobs/{id}/frames", Access::key, routes::job_frames},
    Route{"GET", "/v1/jobs/{id}/meshes", Access::key, routes::job_meshes},
    Route{"GET", "/v1/jobs/{id}/result.glb", Access::key, routes::job_glb},
    Route{"POST", "/v1/assets", Access::key, routes::upload_asset},
    Route{"GET", "/v1/assets/{id}", Access::key, routes::get_asset},
};

// Whether the segments match the route's path; the {id} segment is stored in `id`.
bool path_matches(std::string_view path, const std::vector<std::string>& segments,
                  std::string_view& id) {
  std::size_t k = 0;
  while (!path.empty()) {
    path.remove_prefix(1);  // the '/'
    const auto slash = path.find('/');
    const std::string_view part = path.substr(0, slash);
    if (k >= segments.size()) return false;
    if (part == "{id}") {
      id = segments[k];
    } else if (part != segments[k]) {
      return false;
    }
    ++k;
    path = slash == std::string_view::npos ? std::string_view() : path.substr(slash);
  }
  return k == segments.size();
}

bool method_matches(std::string_view route_method, std::string_view method) {
  return route_method == "*" || route_method == method ||
         (route_method == "GET" && method == "HEAD");
}

// Paths under the API (as opposed to the dashboard's files) need a key when keys are configured.
bool api_path(const Target& target) {
  return (!target.segments.empty() && target.segments[0] == "v1") || target.path == "/metrics" ||
         target.path == "/openapi.yaml";
}

}  // namespace

HttpResponse Api::problem(int status, std::string_view type, std::string_view title,
                          std::string_view detail) {
  return server::problem(status, type, title, detail).response();
}

Api::Api(JobService& service, Metrics& metrics, const ApiKeys& keys,
         std::function<WorkerGauges()> workers, ApiOptions options)
    : service_(service),
      metrics_(metrics),
      keys_(keys),
      workers_(std::move(workers)),
      options_(std::move(options)) {}

HttpResponse Api::handle(const HttpRequest& request, const std::optional<LongPoll>& poll) {
  std::string route_label = "unmatched";
  HttpResponse response;
  try {
    response = route(request, poll, route_label);
  } catch (const BadParameter& bad) {
    response = server::problem(400, "invalid-parameter", "Invalid query parameter", bad.message)
                   .error("parameter", bad.name, bad.message)
                   .response();
  } catch (const BlobError&) {
    // Logged with the job by the blob store; retrying will not help, so not a 503.
    response = server::problem(500, "result-unavailable", "Result unavailable",
                               "the stored result of this job is missing or corrupt in the blob "
                               "store; the server log names the blob")
                   .response();
  } catch (const StorageError&) {
    response = server::problem(503, "storage-unavailable", "Storage unavailable",
                               "the job store could not complete the request; retry later")
                   .header("Retry-After", "1")
                   .response();
  } catch (const std::exception&) {
    response = server::problem(500, "internal-error", "Internal error",
                               "the server failed to answer this request; the request id is in the "
                               "X-Request-Id header and the server log")
                   .response();
  }
  // Metrics and logs label a request by its route template only, never by its raw path.
  response.route = std::move(route_label);
  return response;
}

HttpResponse Api::route(const HttpRequest& request, const std::optional<LongPoll>& poll,
                        std::string& label) {
  const std::optional<Target> target = parse_target(request.target);
  if (!target) {
    return server::problem(400, "bad-request", "Invalid request target",
                           "the request target is not a valid path and query (RFC 9112 §3.2.1)")
        .response();
  }
  routes::Context context{request, *target, {}, poll, service_, metrics_, workers_, options_, {}};

  // The first route whose path and method match; the methods of every route with that path
  // make the Allow header of a 405.
  const Route* matched = nullptr;
  bool path_known = false;
  for (const Route& r : kRoutes) {
    std::string_view id;
    if (!path_matches(r.path, target->segments, id)) continue;
    path_known = true;
    if (method_matches(r.method, request.method)) {
      matched = &r;
      context.id = std::string(id);
      label = std::string(r.path);
      break;
    }
  }
  std::string allow;
  if (!matched && path_known) {
    for (const Route& r : kRoutes) {
      std::string_view id;
      if (!path_matches(r.path, target->segments, id)) continue;
      label = std::string(r.path);
      if (!allow.empty()) allow += ", ";
      allow += r.method == "GET" ? "GET, HEAD" : std::string(r.method);
    }
  }

  const bool get = request.method == "GET" || request.method == "HEAD";
  const bool open = matched ? matched->access == Access::open : !api_path(*target);
  std::optional<ApiKey> key;
  if (!open && keys_.enabled()) {
    const std::string_view auth = request.header("authorization");
    constexpr std::string_view kBearer = "Bearer ";
    if (auth.size() > kBearer.size() && auth.substr(0, kBearer.size()) == kBearer) {
      key = keys_.authenticate(auth.substr(kBearer.size()));
    }
    if (!key) {
      return server::problem(401, "unauthorized", "API key required",
                             "send a valid key as 'Authorization: Bearer KEY'")
          .header("WWW-Authenticate", "Bearer realm=\"brisance\"")
          .response();
    }
    const bool computes = matched && matched->access == Access::read;
    if (!get && !computes && key->scope == Scope::read) {
      return server::problem(403, "forbidden", "Write scope required",
                             "the API key '" + key->name + "' may only read")
          .response();
    }
  }

  context.key = std::move(key);
  if (matched) return matched->handler(context);
  if (!allow.empty()) return method_not_allowed(allow);

  // Outside the API: the dashboard's files.
  if (!api_path(*target)) {
    if (!get) return method_not_allowed("GET, HEAD");
    if (auto file = routes::static_file(context)) {
      label = "/{static}";
      return std::move(*file);
    }
  }
  return not_found("no resource at " + target->path);
}

}  // namespace brisance::server
