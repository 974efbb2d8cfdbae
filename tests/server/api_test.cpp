// The HTTP API end to end: a real server on an ephemeral port, a real HTTP client, a real
// SQLite file.
#include <cstring>
#include <map>
#include <thread>

#include <gtest/gtest.h>

#include "server/api_keys.hpp"
#include "tests/server/test_server.hpp"

namespace brisance::testing {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string submit(TestServer& server, const json& scene, const Headers& headers = {}) {
  const ClientResponse r = server.request("POST", "/v1/jobs", job_body(scene), headers);
  EXPECT_EQ(r.status, 202) << r.body;
  return json::parse(r.body).at("id").get<std::string>();
}

// Long-polls the job until its status is `status` (or the deadline passes).
json wait_for(TestServer& server, const std::string& id, std::string_view status,
              std::chrono::seconds limit = std::chrono::seconds(120)) {
  const auto deadline = Clock::now() + limit;
  json job = server.get_json("/v1/jobs/" + id);
  while (job.at("status") != status && Clock::now() < deadline) {
    job = server.get_json("/v1/jobs/" + id + "?wait=5");
  }
  return job;
}

TEST(Api, JobLifecycleFromSubmissionToEveryResultForm) {
  TestServer server;
  const ClientResponse posted = server.request("POST", "/v1/jobs", job_body(quick_scene()));
  ASSERT_EQ(posted.status, 202) << posted.body;
  const json accepted = json::parse(posted.body);
  const std::string id = accepted.at("id");
  EXPECT_EQ(posted.header("location"), "/v1/jobs/" + id);
  EXPECT_FALSE(posted.header("retry-after").empty());
  EXPECT_FALSE(posted.header("x-request-id").empty());

  const json done = wait_for(server, id, "succeeded");
  ASSERT_EQ(done.at("status"), "succeeded") << done.dump();
  // The job's JSON is written as text; it must be exactly what the JSON library would write.
  const std::string text = server.request("GET", "/v1/jobs/" + id).body;
  EXPECT_EQ(json::parse(text).dump(), text);
  EXPECT_EQ(done.at("links").at("glb"), "/v1/jobs/" + id + "/result.glb");
  EXPECT_EQ(done.at("progress"), 1.0);
  EXPECT_EQ(done.at("attempts"), 1);
  EXPECT_FALSE(done.at("started_at").is_null());
  EXPECT_FALSE(done.at("finished_at").is_null());
  EXPECT_GT(done.at("stats").at("steps").get<int>(), 0);

  const json result = server.get_json("/v1/jobs/" + id + "/result");
  ASSERT_EQ(result.at("bodies").size(), 2u);
  EXPECT_EQ(result.at("bodies")[0].at("name"), "near");
  EXPECT_EQ(result.at("frame_count"), 31);  // 0 s to 1 s at 30 fps
  EXPECT_EQ(result.at("final_state").size(), 2u);

  // The near block is pushed away from the charge along +z.
  const json frames = server.get_json("/v1/jobs/" + id + "/frames?from=0&to=31&bodies=0");
  ASSERT_EQ(frames.at("frames").size(), 31u);
  const double z0 = frames.at("frames")[0].at("poses")[0].at("position")[2];
  const double z1 = frames.at("frames")[30].at("poses")[0].at("position")[2];
  EXPECT_NEAR(z0, 6.0, 1e-6);
  EXPECT_GT(z1, z0 + 0.01);

  // The binary form carries the same numbers.
  const ClientResponse binary = server.request("GET", "/v1/jobs/" + id + "/frames?from=30&bodies=0",
                                               {}, {{"Accept", "application/octet-stream"}});
  ASSERT_EQ(binary.status, 200);
  EXPECT_EQ(binary.header("content-type"), "application/octet-stream");
  ASSERT_EQ(binary.body.size(), 4u + 3 * 4 + 4 + 8 + 7 * 4);
  EXPECT_EQ(binary.body.substr(0, 4), "BRF1");
  std::uint32_t first = 0, count = 0;
  std::memcpy(&first, binary.body.data() + 4, 4);
  std::memcpy(&count, binary.body.data() + 8, 4);
  EXPECT_EQ(first, 30u);
  EXPECT_EQ(count, 1u);
  float z = 0;
  std::memcpy(&z, binary.body.data() + 20 + 8 + 2 * 4, 4);
  EXPECT_FLOAT_EQ(z, static_cast<float>(z1));

  const json meshes = server.get_json("/v1/jobs/" + id + "/meshes");
  EXPECT_EQ(meshes.at("bodies")[0].at("mesh").at("triangles").size(), 12u);

  const ClientResponse glb = server.request("GET", "/v1/jobs/" + id + "/result.glb");
  ASSERT_EQ(glb.status, 200);
  EXPECT_EQ(glb.header("content-type"), "model/gltf-binary");
  EXPECT_EQ(glb.body.substr(0, 4), "glTF");

  // The scene comes back as it was submitted.
  EXPECT_EQ(server.get_json("/v1/jobs/" + id + "/scene"), quick_scene());

  const json list = server.get_json("/v1/jobs?status=succeeded");
  ASSERT_EQ(list.at("jobs").size(), 1u);
  EXPECT_EQ(list.at("jobs")[0].at("id"), id);
}

TEST(Api, EveryValidationProblemIsReportedWithItsPointer) {
  TestServer server;
  json scene = quick_scene();
  scene["objects"][0]["mass"] = -1;
  scene["simulation"]["frame_rate"] = "fast";
  const ClientResponse r =
      server.request("POST", "/v1/jobs", json{{"scene", scene}, {"colour", "red"}}.dump());
  ASSERT_EQ(r.status, 422);
  EXPECT_EQ(r.header("content-type"), "application/problem+json");
  const json problem = json::parse(r.body);
  EXPECT_EQ(problem.at("type"), "urn:brisance:problem:invalid-scene");
  std::vector<std::string> pointers;
  for (const json& e : problem.at("errors"))
    pointers.push_back(e.at("pointer"));
  EXPECT_NE(std::find(pointers.begin(), pointers.end(), "/colour"), pointers.end());
  EXPECT_NE(std::find(pointers.begin(), pointers.end(), "/scene/objects/0/mass"), pointers.end());
  EXPECT_NE(std::find(pointers.begin(), pointers.end(), "/scene/simulation/frame_rate"),
            pointers.end());
  // Nothing was queued.
  EXPECT_TRUE(server.get_json("/v1/jobs").at("jobs").empty());
}

TEST(Api, ClientErrorsAreProblemsWithStableTypes) {
  TestServerOptions small_bodies;
  small_bodies.body_limit_bytes = 4096;
  TestServer server(small_bodies);
  auto type_of = [](const ClientResponse& r) {
    EXPECT_EQ(r.header("content-type"), "application/problem+json") << r.status << " " << r.body;
    return json::parse(r.body).at("type").get<std::string>();
  };
  const ClientResponse malformed = server.request("POST", "/v1/jobs", "{\"scene\": ");
  EXPECT_EQ(malformed.status, 400);
  EXPECT_EQ(type_of(malformed), "urn:brisance:problem:malformed-json");

  const ClientResponse missing = server.request("GET", "/v1/jobs/jdoesnotexist");
  EXPECT_EQ(missing.status, 404);
  EXPECT_EQ(type_of(missing), "urn:brisance:problem:not-found");

  const ClientResponse method = server.request("PUT", "/v1/jobs");
  EXPECT_EQ(method.status, 405);
  EXPECT_EQ(method.header("allow"), "GET, HEAD, POST");
  EXPECT_EQ(type_of(method), "urn:brisance:problem:method-not-allowed");

  const ClientResponse media =
      server.request("POST", "/v1/jobs", job_body(quick_scene()), {{"Content-Type", "text/csv"}});
  EXPECT_EQ(media.status, 415);
  EXPECT_EQ(type_of(media), "urn:brisance:problem:unsupported-media-type");

  const ClientResponse large = server.request("POST", "/v1/jobs", std::string(10000, ' '));
  EXPECT_EQ(large.status, 413);
  EXPECT_EQ(type_of(large), "urn:brisance:problem:payload-too-large");

  const ClientResponse parameter = server.request("GET", "/v1/jobs?limit=0");
  EXPECT_EQ(parameter.status, 400);
  EXPECT_EQ(type_of(parameter), "urn:brisance:problem:invalid-parameter");
  EXPECT_EQ(json::parse(parameter.body).at("errors")[0].at("parameter"), "limit");

  const ClientResponse status = server.request("GET", "/v1/jobs?status=sleeping");
  EXPECT_EQ(status.status, 400);

  const ClientResponse blast = server.request("GET", "/v1/blast?charge_kg=100");
  EXPECT_EQ(blast.status, 400);
  EXPECT_EQ(json::parse(blast.body).at("errors")[0].at("parameter"), "distance_m");

  const ClientResponse unknown = server.request("GET", "/v2/anything");
  EXPECT_EQ(unknown.status, 404);
}

TEST(Api, ResultsOfUnfinishedJobsAreConflictsAndFramesNegotiateTheirType) {
  TestServer server(with_workers(0));
  const std::string id = submit(server, quick_scene());
  const ClientResponse early = server.request("GET", "/v1/jobs/" + id + "/result");
  EXPECT_EQ(early.status, 409);
  EXPECT_EQ(json::parse(early.body).at("type"), "urn:brisance:problem:result-not-ready");
  EXPECT_FALSE(early.header("retry-after").empty());
  const ClientResponse glb = server.request("GET", "/v1/jobs/" + id + "/result.glb");
  EXPECT_EQ(glb.status, 409);

  TestServer done_server;
  const std::string done = submit(done_server, quick_scene());
  ASSERT_EQ(wait_for(done_server, done, "succeeded").at("status"), "succeeded");
  const ClientResponse png =
      done_server.request("GET", "/v1/jobs/" + done + "/frames", {}, {{"Accept", "image/png"}});
  EXPECT_EQ(png.status, 406);
  const ClientResponse bad_body =
      done_server.request("GET", "/v1/jobs/" + done + "/frames?bodies=0,7");
  EXPECT_EQ(bad_body.status, 400);
  const ClientResponse bad_range =
      done_server.request("GET", "/v1/jobs/" + done + "/frames?from=40");
  EXPECT_EQ(bad_range.status, 400);
}

TEST(Api, IdempotencyKeyReturnsTheSameJobAndRejectsAnotherBody) {
  TestServer server(with_workers(0));
  const Headers key = {{"Idempotency-Key", "pipeline-run-42"}};
  const ClientResponse first = server.request("POST", "/v1/jobs", job_body(quick_scene()), key);
  ASSERT_EQ(first.status, 202);
  const ClientResponse again = server.request("POST", "/v1/jobs", job_body(quick_scene()), key);
  EXPECT_EQ(again.status, 200);
  EXPECT_EQ(json::parse(again.body).at("id"), json::parse(first.body).at("id"));
  EXPECT_EQ(again.header("location"), first.header("location"));

  const ClientResponse other = server.request("POST", "/v1/jobs", job_body(quick_scene(), 5), key);
  EXPECT_EQ(other.status, 422);
  EXPECT_EQ(json::parse(other.body).at("type"), "urn:brisance:problem:idempotency-key-reused");
  EXPECT_EQ(server.get_json("/v1/jobs").at("jobs").size(), 1u);
}

TEST(Api, EtagGivesNotModifiedUntilTheJobChanges) {
  TestServer server(with_workers(0));
  const std::string id = submit(server, quick_scene());
  const ClientResponse first = server.request("GET", "/v1/jobs/" + id);
  const std::string etag = first.header("etag");
  ASSERT_FALSE(etag.empty());
  const ClientResponse same =
      server.request("GET", "/v1/jobs/" + id, {}, {{"If-None-Match", etag}});
  EXPECT_EQ(same.status, 304);
  EXPECT_TRUE(same.body.empty());
  ASSERT_EQ(server.request("POST", "/v1/jobs/" + id + "/cancel").status, 200);
  const ClientResponse changed =
      server.request("GET", "/v1/jobs/" + id, {}, {{"If-None-Match", etag}});
  EXPECT_EQ(changed.status, 200);
  EXPECT_NE(changed.header("etag"), etag);

  // Lists and the queue view are validated by ETag too, so idle polling costs no body.
  const ClientResponse queue = server.request("GET", "/v1/queue");
  EXPECT_EQ(
      server.request("GET", "/v1/queue", {}, {{"If-None-Match", queue.header("etag")}}).status,
      304);
}

TEST(Api, LongPollReturnsWhenTheJobChangesAndOtherwiseAtItsDeadline) {
  TestServer server(with_workers(0));
  const std::string id = submit(server, quick_scene());

  // Nothing happens: the poll ends at its deadline with the unchanged job.
  const auto start = Clock::now();
  const ClientResponse idle = server.request("GET", "/v1/jobs/" + id + "?wait=1");
  const double idle_s = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_EQ(idle.status, 200);
  EXPECT_GE(idle_s, 0.9);

  // A cancel half a second in wakes the poll at once.
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    http_request(server.port(), "POST", "/v1/jobs/" + id + "/cancel");
  });
  const auto poll_start = Clock::now();
  const ClientResponse woken = server.request("GET", "/v1/jobs/" + id + "?wait=20");
  const double woken_s = std::chrono::duration<double>(Clock::now() - poll_start).count();
  canceller.join();
  EXPECT_EQ(json::parse(woken.body).at("status"), "cancelled");
  EXPECT_LT(woken_s, 5.0);

  // Waiting is bounded.
  EXPECT_EQ(server.request("GET", "/v1/jobs/" + id + "?wait=31").status, 400);
}

TEST(Api, CancelStopsQueuedJobsAtOnceAndRunningJobsWithinAStep) {
  TestServer server(with_workers(1));
  const std::string running = submit(server, slow_scene());
  const std::string queued = submit(server, quick_scene());
  ASSERT_EQ(wait_for(server, running, "running").at("status"), "running");

  const ClientResponse q = server.request("POST", "/v1/jobs/" + queued + "/cancel");
  EXPECT_EQ(q.status, 200);
  EXPECT_EQ(json::parse(q.body).at("status"), "cancelled");

  const auto start = Clock::now();
  const ClientResponse r = server.request("POST", "/v1/jobs/" + running + "/cancel");
  EXPECT_EQ(r.status, 202);
  EXPECT_TRUE(json::parse(r.body).at("cancel_requested").get<bool>());
  const json stopped = wait_for(server, running, "cancelled", std::chrono::seconds(30));
  EXPECT_EQ(stopped.at("status"), "cancelled");
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 10.0);

  const ClientResponse twice = server.request("POST", "/v1/jobs/" + running + "/cancel");
  EXPECT_EQ(twice.status, 409);
  EXPECT_EQ(json::parse(twice.body).at("type"), "urn:brisance:problem:job-finished");
}

TEST(Api, DeleteRemovesTheJobAndItsResults) {
  TestServer server;
  const std::string id = submit(server, quick_scene());
  ASSERT_EQ(wait_for(server, id, "succeeded").at("status"), "succeeded");
  EXPECT_EQ(server.request("DELETE", "/v1/jobs/" + id).status, 204);
  EXPECT_EQ(server.request("GET", "/v1/jobs/" + id).status, 404);
  EXPECT_EQ(server.request("GET", "/v1/jobs/" + id + "/frames").status, 404);
  EXPECT_EQ(server.request("DELETE", "/v1/jobs/" + id).status, 404);
  EXPECT_TRUE(server.storage().result_bodies(id).empty());
}

TEST(Api, FullQueueAnswers429WithRetryAfter) {
  TestServerOptions small_queue = with_workers(0);
  small_queue.max_queue = 2;
  TestServer server(small_queue);
  submit(server, quick_scene());
  submit(server, quick_scene());
  // The queued count may be cached for up to 100 ms.
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  const ClientResponse full = server.request("POST", "/v1/jobs", job_body(quick_scene()));
  EXPECT_EQ(full.status, 429);
  EXPECT_EQ(json::parse(full.body).at("type"), "urn:brisance:problem:queue-full");
  EXPECT_FALSE(full.header("retry-after").empty());
}

TEST(Api, ListPagesWithACursorNewestFirst) {
  TestServer server(with_workers(0));
  std::vector<std::string> ids;
  for (int i = 0; i < 5; ++i)
    ids.push_back(submit(server, quick_scene()));
  std::vector<std::string> seen;
  std::string target = "/v1/jobs?limit=2";
  for (int page = 0; page < 5; ++page) {
    const json body = server.get_json(target);
    for (const json& job : body.at("jobs"))
      seen.push_back(job.at("id"));
    if (body.at("next_cursor").is_null()) break;
    target = "/v1/jobs?limit=2&cursor=" + body.at("next_cursor").get<std::string>();
  }
  ASSERT_EQ(seen.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i)
    EXPECT_EQ(seen[i], ids[4 - i]);
}

TEST(Api, JobsCarryANameAndLabelsAndAreListedByThem) {
  TestServer server(with_workers(0));
  const auto submit_named = [&](const std::string& name, const json& labels) {
    const json body = {{"scene", quick_scene()}, {"name", name}, {"labels", labels}};
    const ClientResponse r = server.request("POST", "/v1/jobs", body.dump());
    EXPECT_EQ(r.status, 202) << r.body;
    const json job = json::parse(r.body);
    EXPECT_EQ(job.at("name"), name);
    EXPECT_EQ(job.at("labels"), labels);
    return job.at("id").get<std::string>();
  };
  const std::string a = submit_named("Facade, shot 12", {{"shot", "sq010"}, {"artist", "kim"}});
  const std::string b = submit_named("Facade, shot 13", {{"shot", "sq010"}});
  const std::string c = submit_named("Crate", {{"shot", "sq020"}, {"take", "2"}});
  const std::string plain = submit(server, quick_scene());
  const json stored = server.get_json("/v1/jobs/" + a);
  EXPECT_EQ(stored.at("name"), "Facade, shot 12");
  EXPECT_EQ(stored.at("labels").at("artist"), "kim");
  EXPECT_EQ(server.get_json("/v1/jobs/" + plain).at("name"), "");
  EXPECT_EQ(server.get_json("/v1/jobs/" + plain).at("labels"), json::object());

  const auto ids = [&](const std::string& query) {
    std::vector<std::string> out;
    const json page = server.get_json("/v1/jobs?" + query);
    for (const json& job : page.at("jobs"))
      out.push_back(job.at("id"));
    return out;
  };
  EXPECT_EQ(ids("label=shot=sq010"), (std::vector<std::string>{b, a}));
  EXPECT_EQ(ids("label=shot=sq010,artist=kim"), (std::vector<std::string>{a}));
  EXPECT_EQ(ids("label=take"), (std::vector<std::string>{c}));
  EXPECT_EQ(ids("name=facade"), (std::vector<std::string>{b, a}));
  EXPECT_EQ(ids("name=shot+13"), (std::vector<std::string>{b}));

  // The next page keeps the filter.
  const ClientResponse first = server.request("GET", "/v1/jobs?limit=1&label=shot%3Dsq010");
  ASSERT_EQ(first.status, 200);
  const std::string link = std::string(first.header("link"));
  ASSERT_NE(link.find("label=shot%3Dsq010"), std::string::npos) << link;
  const std::string next = link.substr(1, link.find('>') - 1);
  const json second = server.get_json(next);
  ASSERT_EQ(second.at("jobs").size(), 1u);
  EXPECT_EQ(second.at("jobs")[0].at("id"), a);

  EXPECT_EQ(server.request("GET", "/v1/jobs?label=sh%20ot").status, 400);
  EXPECT_EQ(server.request("GET", "/v1/jobs?label=a,b,c,d,e,f,g,h,i").status, 400);
}

TEST(Api, BadNamesAndLabelsAreEachReportedWithTheirPointer) {
  TestServer server(with_workers(0));
  const json body = {{"scene", quick_scene()},
                     {"name", std::string(201, 'x')},
                     {"labels", {{"shot", 12}, {"bad key", "x"}, {"ok", "a,b"}}},
                     {"label", {{"shot", "sq010"}}}};
  const ClientResponse r = server.request("POST", "/v1/jobs", body.dump());
  ASSERT_EQ(r.status, 422) << r.body;
  std::map<std::string, std::string> errors;
  const json problem = json::parse(r.body);
  for (const json& e : problem.at("errors"))
    errors[e.at("pointer")] = e.at("detail");
  EXPECT_EQ(errors.size(), 5u) << r.body;
  EXPECT_NE(errors["/name"].find("at most 200"), std::string::npos);
  EXPECT_NE(errors["/labels/shot"].find("strings"), std::string::npos);
  EXPECT_NE(errors["/labels/bad key"].find("letters"), std::string::npos);
  EXPECT_NE(errors["/labels/ok"].find("','"), std::string::npos);
  EXPECT_NE(errors["/label"].find("did you mean 'labels'"), std::string::npos);
  EXPECT_EQ(server
                .request("POST", "/v1/jobs",
                         json{{"scene", quick_scene()}, {"labels", {"a", "b"}}}.dump())
                .status,
            422);
  EXPECT_TRUE(server.get_json("/v1/jobs").at("jobs").empty());
}

TEST(Api, HigherPriorityJobsRunFirst) {
  TestServer server(with_workers(0));
  const std::string low = submit(server, quick_scene());
  const ClientResponse high_r = server.request("POST", "/v1/jobs", job_body(quick_scene(), 10));
  const std::string high = json::parse(high_r.body).at("id");
  auto claimed = server.storage().claim_next("test", server::now_ms(), 1000);
  ASSERT_TRUE(claimed);
  EXPECT_EQ(claimed->job.id, high);
  EXPECT_NE(claimed->job.id, low);
}

TEST(Api, ApiKeysGuardEverythingButTheProbes) {
  const std::string read_key = "bk_read_key_for_tests";
  const std::string write_key = "bk_write_key_for_tests";
  TestServerOptions options = with_workers(0);
  options.api_keys = server::api_key_line("reader", server::Scope::read, read_key) + "\n" +
                     server::api_key_line("writer", server::Scope::write, write_key);
  TestServer server(options);
  EXPECT_EQ(server.request("GET", "/healthz").status, 200);
  EXPECT_EQ(server.request("GET", "/readyz").status, 503);  // no workers: not ready

  const ClientResponse none = server.request("GET", "/v1/jobs");
  EXPECT_EQ(none.status, 401);
  EXPECT_EQ(none.header("www-authenticate"), "Bearer realm=\"brisance\"");
  EXPECT_EQ(server.request("GET", "/metrics").status, 401);
  EXPECT_EQ(server.request("GET", "/v1/jobs", {}, {{"Authorization", "Bearer wrong"}}).status, 401);
  EXPECT_EQ(server.request("GET", "/v1/jobs", {}, {{"Authorization", "Bearer " + read_key}}).status,
            200);
  const ClientResponse forbidden = server.request("POST", "/v1/jobs", job_body(quick_scene()),
                                                  {{"Authorization", "Bearer " + read_key}});
  EXPECT_EQ(forbidden.status, 403);
  // The calculators only compute: a read key may POST to them.
  const json pulse = {{"element",
                       {{"mass_kg", 100},
                        {"loaded_area_m2", 1},
                        {"resistance", {{"type", "elastic"}, {"stiffness_n_per_m", 1e6}}}}},
                      {"pulse", {{"peak_kpa", 10}, {"duration_ms", 1}}}};
  EXPECT_EQ(
      server
          .request("POST", "/v1/response", pulse.dump(), {{"Authorization", "Bearer " + read_key}})
          .status,
      200);
  EXPECT_EQ(server.request("POST", "/v1/response", pulse.dump()).status, 401);
  EXPECT_EQ(server
                .request("POST", "/v1/jobs", job_body(quick_scene()),
                         {{"Authorization", "Bearer " + write_key}})
                .status,
            202);
}

// Jobs belong to the key that submitted them: another key neither lists, reads, cancels nor
// deletes them, and idempotency keys are each key's own; an admin key sees every job.
TEST(Api, EachKeySeesOnlyItsOwnJobsAndAdminsSeeAll) {
  const std::string alice_key = "bk_alice_key_for_tests";
  const std::string bob_key = "bk_bob_key_for_tests";
  const std::string root_key = "bk_root_key_for_tests";
  TestServerOptions options = with_workers(0);
  options.api_keys = server::api_key_line("alice", server::Scope::write, alice_key) + "\n" +
                     server::api_key_line("bob", server::Scope::write, bob_key) + "\n" +
                     server::api_key_line("root", server::Scope::admin, root_key);
  TestServer server(options);
  const Headers alice = {{"Authorization", "Bearer " + alice_key}, {"Idempotency-Key", "k1"}};
  const Headers bob = {{"Authorization", "Bearer " + bob_key}, {"Idempotency-Key", "k1"}};
  const Headers root = {{"Authorization", "Bearer " + root_key}};
  const std::string id = submit(server, quick_scene(), alice);
  json other = quick_scene();
  other["simulation"]["duration"] = 0.5;
  // The same idempotency key with another body is bob's own new job, not a conflict with alice's.
  const std::string bobs = submit(server, other, bob);
  EXPECT_NE(bobs, id);

  const auto ids = [&](const Headers& who) {
    std::vector<std::string> out;
    const json page = json::parse(server.request("GET", "/v1/jobs", {}, who).body);
    for (const json& job : page.at("jobs"))
      out.push_back(job.at("id"));
    return out;
  };
  EXPECT_EQ(ids(alice), std::vector<std::string>{id});
  EXPECT_EQ(ids(bob), std::vector<std::string>{bobs});
  EXPECT_EQ(ids(root).size(), 2u);

  for (const auto& [method, path] :
       std::vector<std::pair<std::string, std::string>>{{"GET", "/v1/jobs/" + id},
                                                        {"GET", "/v1/jobs/" + id + "/scene"},
                                                        {"GET", "/v1/jobs/" + id + "/result"},
                                                        {"POST", "/v1/jobs/" + id + "/cancel"},
                                                        {"DELETE", "/v1/jobs/" + id}}) {
    EXPECT_EQ(server.request(method, path, {}, bob).status, 404) << method << " " << path;
  }
  EXPECT_EQ(server.request("GET", "/v1/jobs/" + id, {}, alice).status, 200);
  EXPECT_EQ(server.request("GET", "/v1/jobs/" + id, {}, root).status, 200);
  EXPECT_EQ(server.request("POST", "/v1/jobs/" + id + "/cancel", {}, root).status, 200);
  EXPECT_EQ(server.request("DELETE", "/v1/jobs/" + bobs, {}, bob).status, 204);
}

TEST(Api, KeepAliveServesSeveralRequestsOnOneConnectionAndEchoesRequestIds) {
  TestServer server(with_workers(0));
  Connection connection(server.port());
  for (int i = 0; i < 3; ++i) {
    const ClientResponse r =
        connection.request("GET", "/healthz", {}, {{"X-Request-Id", "abc-" + std::to_string(i)}});
    EXPECT_EQ(r.status, 200);
    EXPECT_EQ(r.header("x-request-id"), "abc-" + std::to_string(i));
  }
  // Two pipelined requests are answered in order.
  const ClientResponse first = connection.raw(
      "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\nGET /v1/queue HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_EQ(first.body, "{\"status\":\"ok\"}");
}

TEST(Api, MalformedHttpIsA400AndTheConnectionCloses) {
  TestServer server(with_workers(0));
  Connection connection(server.port());
  const ClientResponse r = connection.raw("GARBAGE\r\n\r\n");
  EXPECT_EQ(r.status, 400);
  EXPECT_TRUE(connection.closed_by_server());
}

// RFC 9112 §6.1: a request whose final transfer coding is not chunked is a 400 and the
// connection closes, so what follows it is never served as a second request.
TEST(Api, TransferEncodingOtherThanChunkedIsA400AndCloses) {
  TestServer server(with_workers(0));
  for (const std::string coding : {"identity", "gzip", "xchunked", "chunked, gzip"}) {
    Connection connection(server.port());
    const ClientResponse r =
        connection.raw("GET /healthz HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: " + coding +
                       "\r\n\r\nGET /v1/queue HTTP/1.1\r\nHost: x\r\n\r\n");
    EXPECT_EQ(r.status, 400) << coding;
    EXPECT_TRUE(connection.closed_by_server()) << coding;
  }
  Connection chunked(server.port());
  EXPECT_EQ(
      chunked.raw("GET /healthz HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n")
          .status,
      200);
}

TEST(Api, ConnectionsAboveTheCapGet503AndClose) {
  TestServerOptions options = with_workers(0);
  options.max_connections = 2;
  TestServer server(options);
  Connection first(server.port());
  Connection second(server.port());
  EXPECT_EQ(first.request("GET", "/healthz").status, 200);
  EXPECT_EQ(second.request("GET", "/healthz").status, 200);
  Connection third(server.port());
  const ClientResponse refused = third.request("GET", "/healthz");
  EXPECT_EQ(refused.status, 503);
  EXPECT_EQ(json::parse(refused.body).at("type"), "urn:brisance:problem:overloaded");
  EXPECT_EQ(refused.header("retry-after"), "1");
  EXPECT_TRUE(third.closed_by_server());
  EXPECT_EQ(first.request("GET", "/healthz").status, 200);  // the open ones keep working
}

// A store that cannot take a result (here: a database capped below the result's size, which
// fails as a full disk does; 1 001 frames of 100 blocks, so that even compressed it does not fit)
// is not the job's fault: the job goes back to the queue, never ends failed, and no SQL text
// reaches the client.
TEST(Api, AResultTheStoreCannotTakeSendsTheJobBackToTheQueue) {
  if (test_store_is_postgres()) {
    GTEST_SKIP() << "the size cap is SQLite's (max_page_count); PostgreSQL's disk is its server's";
  }
  if (std::getenv("BRISANCE_TEST_BLOBS")) {
    GTEST_SKIP() << "results go to the blob folder (BlobApi.* tests an unwritable one)";
  }
  TestServerOptions options;
  options.max_db_bytes = 192 * 1024;
  options.store_failure_pause = std::chrono::milliseconds(100);
  TestServer server(options);
  const json scene = json::parse(R"({
    "charges": [{"position": [0, 0.5, 0], "mass": 5}],
    "generators": [{"type": "blocks", "name": "b", "counts": [10, 1, 10], "size": [0.2, 0.2, 0.2],
                    "spacing": [0.05, 0, 0.05], "density": 300, "position": [0, 0, 3]}],
    "simulation": {"duration": 1, "frame_rate": 1000}})");
  const std::string id = submit(server, scene);
  bool ran = false, requeued = false;
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  while (Clock::now() < deadline && !requeued) {
    const json job = server.get_json("/v1/jobs/" + id);
    ASSERT_NE(job.at("status"), "failed") << job.dump();
    ASSERT_NE(job.at("status"), "succeeded") << job.dump();
    ASSERT_TRUE(job.at("error").is_null()) << job.dump();
    if (job.at("status") == "running") ran = true;
    if (ran && job.at("status") == "queued") {
      requeued = true;
      EXPECT_EQ(job.at("attempts").get<int>(), 0) << "a storage failure does not count an attempt";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_TRUE(ran);
  EXPECT_TRUE(requeued);
}

// Below the free-space floor new work is refused with 507 and the server says it is not ready,
// while reads, cancels and deletes (which make room) keep working.
TEST(Api, BelowTheFreeSpaceFloorSubmissionsGet507AndDeletesStillWork) {
  TestServer normal(with_workers(0));
  const std::string id = submit(normal, quick_scene());
  EXPECT_EQ(normal.request("GET", "/readyz").status, 503);  // no workers, but the disk is fine
  EXPECT_EQ(json::parse(normal.request("GET", "/readyz").body).at("disk"), "ok");

  TestServerOptions options = with_workers(0);
  options.min_free_bytes = std::uint64_t{1} << 62;  // more than any disk has
  TestServer full(options);
  const ClientResponse refused = full.request("POST", "/v1/jobs", job_body(quick_scene()));
  EXPECT_EQ(refused.status, 507);
  EXPECT_EQ(json::parse(refused.body).at("type"), "urn:brisance:problem:insufficient-storage");
  EXPECT_FALSE(refused.header("retry-after").empty());
  const json ready = json::parse(full.request("GET", "/readyz").body);
  EXPECT_EQ(ready.at("disk"), "low");
  EXPECT_EQ(full.request("GET", "/v1/jobs").status, 200);
  EXPECT_EQ(full.request("GET", "/v1/jobs/" + id).status, 404);  // another store
  EXPECT_EQ(normal.request("DELETE", "/v1/jobs/" + id).status, 204);
}

TEST(Api, AnyBytesInTargetsGiveProblemsNotCrashes) {
  TestServer server(with_workers(0));
  const ClientResponse bad_name =
      server.request("GET", "/v1/blast?charge_kg=1&distance_m=10&explosive=%ff");
  EXPECT_EQ(bad_name.status, 400);
  const json problem = json::parse(bad_name.body);  // valid JSON, hence valid UTF-8
  EXPECT_EQ(problem.at("errors")[0].at("parameter"), "explosive");
  EXPECT_NE(problem.at("detail").get<std::string>().find("\xEF\xBF\xBD"), std::string::npos);
  for (const std::string path : {"/v1/jobs/%ff%fe", "/v1/jobs/%c3%28/result", "/v1/jobs/j%00x"}) {
    const ClientResponse r = server.request("GET", path);
    EXPECT_EQ(r.status, 404) << path;
    EXPECT_TRUE(json::accept(r.body)) << path;
  }
  const ClientResponse invalid = server.request("GET", "/v1/jobs/%zz");
  EXPECT_EQ(invalid.status, 400);
  EXPECT_EQ(json::parse(invalid.body).at("type"), "urn:brisance:problem:bad-request");
  EXPECT_EQ(server.request("GET", "/healthz").status, 200);  // still serving
}

TEST(Api, RouteTableAnswers405WithAllowAnd404OutsideIt) {
  TestServer server(with_workers(0));
  const ClientResponse put = server.request("PUT", "/v1/jobs");
  EXPECT_EQ(put.status, 405);
  EXPECT_EQ(put.header("allow"), "GET, HEAD, POST");
  const ClientResponse post_job = server.request("POST", "/v1/jobs/j1");
  EXPECT_EQ(post_job.status, 405);
  EXPECT_EQ(post_job.header("allow"), "GET, HEAD, DELETE");
  EXPECT_EQ(server.request("POST", "/healthz").status, 200);  // probes answer every method
  EXPECT_EQ(server.request("GET", "/v1/nothing-here").status, 404);
  EXPECT_EQ(server.request("GET", "/v1/jobs/j1/nothing").status, 404);
  // A "+" in a path is a plus sign, not a space; "%2F" stays inside its segment.
  const ClientResponse plus = server.request("GET", "/v1/jobs/a+b");
  EXPECT_EQ(plus.status, 404);
  EXPECT_NE(json::parse(plus.body).at("detail").get<std::string>().find("'a+b'"),
            std::string::npos);
  const ClientResponse slash = server.request("GET", "/v1/jobs/a%2Fb");
  EXPECT_EQ(slash.status, 404);
  EXPECT_NE(json::parse(slash.body).at("detail").get<std::string>().find("'a/b'"),
            std::string::npos);
  // In a query, "+" is a space, as forms send it: "queued+" is not a status.
  EXPECT_EQ(server.request("GET", "/v1/jobs?status=queued+").status, 400);
}

// Metrics label requests by route template and known method only, so made-up paths and methods
// cannot grow them.
TEST(Api, MetricsLabelsComeFromAClosedSet) {
  TestServer server(with_workers(0));
  for (int i = 0; i < 20; ++i)
    server.request("GET", "/v1/random-" + std::to_string(i));
  server.request("FROBNICATE", "/v1/jobs");
  const std::string metrics = server.request("GET", "/metrics").body;
  EXPECT_EQ(metrics.find("random-"), std::string::npos);
  EXPECT_EQ(metrics.find("FROBNICATE"), std::string::npos);
  EXPECT_NE(metrics.find("route=\"unmatched\",method=\"GET\",status=\"404\""), std::string::npos);
  EXPECT_NE(metrics.find("method=\"other\""), std::string::npos);
}

TEST(Api, MetricsCountRequestsAndJobs) {
  TestServer server;
  const std::string id = submit(server, quick_scene());
  ASSERT_EQ(wait_for(server, id, "succeeded").at("status"), "succeeded");
  const std::string finished = "brisance_jobs_finished_total{outcome=\"succeeded\"} 1";
  const std::string text = server.scrape_metrics_until(finished);
  EXPECT_NE(
      text.find(
          "brisance_http_requests_total{route=\"/v1/jobs\",method=\"POST\",status=\"202\"} 1"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("brisance_jobs{state=\"succeeded\"} 1"), std::string::npos);
  EXPECT_NE(text.find(finished), std::string::npos) << text;
  EXPECT_NE(text.find("brisance_job_run_seconds_count 1"), std::string::npos);
  EXPECT_NE(
      text.find(
          "brisance_http_request_duration_seconds_bucket{route=\"/v1/jobs/{id}\",le=\"+Inf\"}"),
      std::string::npos);
}

TEST(Api, GracefulStopPutsTheRunningJobBackInTheQueue) {
  auto server = std::make_unique<TestServer>(with_workers(1));
  const std::string id = submit(*server, slow_scene());
  ASSERT_EQ(wait_for(*server, id, "running").at("status"), "running");
  server::Storage& storage = server->storage();
  server->stop();  // grace 0: the run is cancelled and released
  const auto job = storage.get_job(id);
  ASSERT_TRUE(job);
  EXPECT_EQ(job->status, server::JobStatus::queued);
  EXPECT_EQ(job->attempts, 0);  // a shutdown does not count as an attempt
}

}  // namespace
}  // namespace brisance::testing
