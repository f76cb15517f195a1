// live_bridge: follows a running pipeline and forwards what it does to web pages over a local
// websocket (Boost.Beast), for the live viewer page (tools/view --live). It reads the processes'
// LCM messages (subscribing on --lcm-url, or reading a growing LCM log with --follow-log, such as
// the run.lcmlog tools/launch records; a message sent in parts once it is whole) and sends each as
// one compact JSON object (see "Live
// messages" in docs/json_schema.md): the terrain, contact surfaces, plan request, root path, each
// contact plan, the steps walked so far, the robot's state every 50 ms of simulated time (with
// joints, torques and the CoM's support margin), the replans' latency and every process's status.
// A page that connects late first gets what came before. It listens on 127.0.0.1 only; GET / returns
// the page given by --page.
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <fcntl.h>
#include <malloc.h>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>
#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <deque>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "rbcp/core/error.h"
#include "rbcp/cli/cli.h"
#include "rbcp/nodes/run_record.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/run_loop.h"
#include "rbcp/transport/wire_check.h"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp/page_socket.h"
#include "view_json.h"

namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using nlohmann::json;
using Text = std::shared_ptr<const std::string>;

/// Messages a slow page may have queued before robot states are dropped for it.
constexpr std::size_t kMaxQueuedStates = 256;
/// Robot states kept for a page that connects late (20 Hz: a quarter of an hour of simulated time).
constexpr std::size_t kMaxKeptStates = 18000;
/// Pages followed at once; more are refused (503) until one leaves.
constexpr std::size_t kMaxPages = 32;
/// Out of file descriptors (or another accept error), the listener waits this long before it
/// accepts again, instead of retrying at once [ms].
constexpr int kAcceptBackoffMs = 200;

class Hub;

/// One page's websocket: a write queue, and a read loop that notices when the page goes.
class Session : public std::enable_shared_from_this<Session> {
 public:
  Session(tcp::socket socket, Hub& hub) : ws_(std::move(socket)), hub_(hub) {}
  void Start(http::request<http::string_body> request);
  /// Queues a message; a robot state is dropped while the page is behind.
  void Send(const Text& text, bool droppable) {
    if (droppable && queue_.size() > kMaxQueuedStates) return;
    queue_.push_back(text);
    if (queue_.size() == 1) Write();
  }

 private:
  void Write() {
    ws_.async_write(net::buffer(*queue_.front()), [self = shared_from_this()](beast::error_code error, std::size_t) {
      if (error) return self->Close();
      self->queue_.pop_front();
      if (!self->queue_.empty()) self->Write();
    });
  }
  void Read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code error, std::size_t) {
      if (error) return self->Close();
      self->buffer_.consume(self->buffer_.size());  // the page has nothing to say
      self->Read();
    });
  }
  void Close();

  websocket::stream<beast::tcp_stream> ws_;
  Hub& hub_;
  beast::flat_buffer buffer_;
  std::deque<Text> queue_;
  bool closed_ = false;
};

/// The run so far, and the pages to tell.
class Hub {
 public:
  Hub(const rbcp::RobotModel& robot, bool quiet) : robot_(robot), quiet_(quiet) {}

  void Join(const std::shared_ptr<Session>& session) {
    sessions_.insert(session);
    Log("a page connected (" + std::to_string(sessions_.size()) + " now)");
    session->Send(Make({{"type", "hello"}, {"schema_version", rbcp::kJsonSchemaVersion}, {"joint_names", JointNames()}}),
                  false);
    for (const Text* cached : {&terrain_, &surfaces_, &request_, &root_path_, &walked_, &plan_}) {
      if (*cached) session->Send(*cached, false);
    }
    for (const Text& s : states_) session->Send(s, false);
    for (const Text& r : replans_) session->Send(r, false);
    for (const auto& [process, status] : statuses_) session->Send(status, false);
  }
  void Leave(const std::shared_ptr<Session>& session) {
    if (sessions_.erase(session)) {
      Log("a page left (" + std::to_string(sessions_.size()) + " now)");
      ::malloc_trim(0);  // a page's buffers go back to the system with it
    }
  }
  bool Full() const { return sessions_.size() >= kMaxPages; }

  /// One LCM message, received at `receive_us` (any clock, the same for every message). A part of
  /// a message sent in parts (TERRAIN/PART) is kept until its message is whole.
  void OnMessage(const std::string& channel, int64_t receive_us, const void* data, unsigned size) {
    const std::string problem =
        joiner_.Add(channel, data, size, [&](const std::string& whole, const void* bytes, std::size_t n) {
          OnWhole(whole, receive_us, bytes, static_cast<unsigned>(n));
        });
    if (!problem.empty()) {
      ++malformed_;
      Log("dropped " + problem);
    }
  }

  /// One whole LCM message.
  void OnWhole(const std::string& channel, int64_t receive_us, const void* data, unsigned size) {
    namespace ch = rbcp::channels;
    try {
      if (channel == ch::kRobotState) {
        rbcp_msgs::robot_state_t msg;
        if (!Decode(msg, data, size)) return;
        const std::size_t before = record_.Trace().size();
        record_.OnRobotState(receive_us, msg);
        if (record_.Trace().size() > before) {
          const auto& controller = record_.Trace().back().controller;
          json j = rbcp::view::RobotStateJson(robot_, msg, controller ? &*controller : nullptr);
          j["type"] = "state";
          const Text text = Make(j);
          if (states_.size() >= kMaxKeptStates) states_.pop_front();
          states_.push_back(text);
          Broadcast(text, true);
        }
      } else if (channel == ch::kControllerStatus) {
        rbcp_msgs::controller_status_t msg;
        if (!Decode(msg, data, size)) return;
        record_.OnControllerStatus(receive_us, msg);
        if (msg.plan_seq != walked_seq_ || msg.steps_done != walked_steps_) {
          walked_seq_ = msg.plan_seq;
          walked_steps_ = msg.steps_done;
          SendWalked();
        }
      } else if (channel == ch::kContactPlan) {
        rbcp_msgs::contact_plan_t msg;
        if (!Decode(msg, data, size)) return;
        const std::size_t before = record_.LatenciesMs().size();
        record_.OnContactPlan(receive_us, msg);
        json j = rbcp::view::ContactPlanJson(msg);
        j["type"] = "plan";
        Cache(plan_, Make(j));
        if (record_.LatenciesMs().size() > before) {
          const Text text = Make({{"type", "replan"}, {"t", record_.LatencyTimesS().back()},
                                  {"latency_ms", record_.LatenciesMs().back()}});
          replans_.push_back(text);
          Broadcast(text, false);
        }
        SendWalked();
      } else if (channel == ch::kTerrain) {
        rbcp_msgs::terrain_mesh_t msg;
        if (!Decode(msg, data, size)) return;
        json j = rbcp::view::TerrainJson(msg);
        j["type"] = "terrain";
        Cache(terrain_, Make(j));
      } else if (channel == ch::kAffordances) {
        rbcp_msgs::affordance_set_t msg;
        if (!Decode(msg, data, size)) return;
        Cache(surfaces_, Make({{"type", "surfaces"}, {"contact_surfaces", rbcp::view::SurfacesJson(msg)}}));
      } else if (channel == ch::kRootPath) {
        rbcp_msgs::root_path_t msg;
        if (!Decode(msg, data, size)) return;
        Cache(root_path_, Make({{"type", "root_path"}, {"root_path", rbcp::view::RootPathJson(msg)}}));
      } else if (channel == ch::kPlanRequest) {
        rbcp_msgs::plan_request_t msg{};
        if (!Decode(msg, data, size)) return;
        Cache(request_, Make({{"type", "request"},
                              {"goal", {{"position", {msg.goal_position[0], msg.goal_position[1]}}, {"yaw", msg.goal_yaw}}}}));
      } else if (channel == ch::kStatus) {
        rbcp_msgs::process_status_t msg;
        if (!Decode(msg, data, size)) return;
        json j = rbcp::view::StatusJson(msg);
        // Heartbeats repeat the same state: a page hears a process again when something changes.
        const std::string key = j["state"].get<std::string>() + '\n' + msg.reason;
        if (status_keys_[msg.process] == key) return;
        status_keys_[msg.process] = key;
        j["type"] = "status";
        const Text text = Make(j);
        statuses_[msg.process] = text;
        Broadcast(text, false);
      }
    } catch (const rbcp::InputError& e) {
      ++malformed_;
      Log("dropped a malformed " + channel + ": " + e.what());
    }
  }

  long Malformed() const { return malformed_; }
  void Log(const std::string& line) const {
    if (!quiet_) std::cerr << "[live_bridge] " << line << std::endl;
  }

 private:
  template <typename Msg>
  bool Decode(Msg& msg, const void* data, unsigned size) {
    if (!rbcp::transport::DecodeMessage(data, size, msg)) return true;
    ++malformed_;
    return false;
  }
  static Text Make(const json& j) { return std::make_shared<const std::string>(j.dump()); }
  static json JointNames() {
    json j;
    rbcp::AddSchemaKeys(j);
    return j["joint_names"];
  }
  /// Keeps `text` as the newest of its kind and sends it when it differs from the one before.
  void Cache(Text& slot, const Text& text) {
    if (slot && *slot == *text) return;
    slot = text;
    Broadcast(text, false);
  }
  /// The steps walked so far (the walked plan), when a plan or the robot's progress changes.
  void SendWalked() {
    if (!record_.Latest()) return;
    // A plan the bridge missed (it started late, or UDP dropped it) is left out.
    std::vector<std::string> missing;
    const rbcp::ContactPlan walked = record_.ExecutedPlan(&missing);
    Cache(walked_, Make({{"type", "walked"}, {"states", rbcp::ContactPlanToJson(walked)}, {"missing_plans", missing}}));
  }
  void Broadcast(const Text& text, bool droppable) {
    for (const auto& s : sessions_) s->Send(text, droppable);
  }

  const rbcp::RobotModel& robot_;
  bool quiet_;
  rbcp::nodes::RunRecord record_;
  std::set<std::shared_ptr<Session>> sessions_;
  Text terrain_, surfaces_, request_, root_path_, plan_, walked_;
  std::deque<Text> states_;
  std::vector<Text> replans_;
  std::map<std::string, Text> statuses_;
  std::map<std::string, std::string> status_keys_;
  int64_t walked_seq_ = -1;
  int walked_steps_ = -1;
  long malformed_ = 0;
  rbcp::transport::PartJoiner joiner_;
};

void Session::Start(http::request<http::string_body> request) {
  rbcp::live_bridge::ConfigurePageSocket(ws_);
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code error) {
    if (error) return;
    self->hub_.Join(self);
    self->Read();
  });
}

void Session::Close() {
  if (closed_) return;
  closed_ = true;
  queue_.clear();
  hub_.Leave(shared_from_this());
}

/// One HTTP connection: the page (GET /) or the upgrade to a websocket (GET /ws).
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Hub& hub, const std::string& page, unsigned short port)
      : stream_(std::move(socket)), hub_(hub), page_(page), port_(port) {
    rbcp::live_bridge::BoundRequest(parser_);
  }

  void Start() {
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, parser_, [self = shared_from_this()](beast::error_code error, std::size_t) {
      if (error) return;
      self->request_ = self->parser_.release();
      self->Handle();
    });
  }

 private:
  void Handle() {
    const std::string target(request_.target());
    const std::string origin(request_[http::field::origin]);
    if (websocket::is_upgrade(request_)) {
      if (target != "/ws" || !rbcp::live_bridge::AllowedOrigin(origin, port_)) {
        hub_.Log("refused a websocket for " + target + " from origin '" + origin + "'");
        return Respond(http::status::forbidden, "text/plain", "live_bridge: websocket at /ws, from a page on disk or this host\n");
      }
      if (hub_.Full()) {
        hub_.Log("refused a page: " + std::to_string(kMaxPages) + " pages are connected already");
        return Respond(http::status::service_unavailable, "text/plain",
                       "live_bridge: " + std::to_string(kMaxPages) + " pages are connected already\n");
      }
      stream_.expires_never();
      std::make_shared<Session>(stream_.release_socket(), hub_)->Start(std::move(request_));
      return;
    }
    if (request_.method() != http::verb::get) {
      return Respond(http::status::method_not_allowed, "text/plain", "live_bridge: GET only\n");
    }
    if (target == "/" || target == "/index.html") {
      if (page_.empty()) {
        return Respond(http::status::not_found, "text/plain",
                       "live_bridge: no page (start it with --page FILE.html, written by tools/view --live)\n");
      }
      return Respond(http::status::ok, "text/html; charset=utf-8", page_);
    }
    Respond(http::status::not_found, "text/plain", "live_bridge: not found\n");
  }

  void Respond(http::status status, const char* type, const std::string& body) {
    auto response = std::make_shared<http::response<http::string_body>>(status, request_.version());
    response->set(http::field::content_type, type);
    response->set(http::field::cache_control, "no-store");
    response->keep_alive(false);
    response->body() = body;
    response->prepare_payload();
    http::async_write(stream_, *response, [self = shared_from_this(), response](beast::error_code, std::size_t) {
      beast::error_code ignored;
      self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    });
  }

  beast::tcp_stream stream_;
  Hub& hub_;
  const std::string& page_;
  unsigned short port_;
  beast::flat_buffer buffer_;
  http::request_parser<http::string_body> parser_;
  http::request<http::string_body> request_;
};

class Listener : public std::enable_shared_from_this<Listener> {
 public:
  Listener(net::io_context& io, const tcp::endpoint& endpoint, Hub& hub, const std::string& page)
      : acceptor_(io, endpoint), backoff_(io), hub_(hub), page_(page) {}
  unsigned short Port() const { return acceptor_.local_endpoint().port(); }
  void Accept() {
    acceptor_.async_accept([self = shared_from_this()](beast::error_code error, tcp::socket socket) {
      if (!self->acceptor_.is_open()) return;
      if (!error) {
        self->accept_failing_ = false;
        std::make_shared<HttpSession>(std::move(socket), self->hub_, self->page_, self->Port())->Start();
        self->Accept();
        return;
      }
      // Out of file descriptors the accept fails at once, again and again: wait before the next.
      if (!self->accept_failing_) self->hub_.Log("cannot accept a connection (" + error.message() + "): waiting");
      self->accept_failing_ = true;
      self->backoff_.expires_after(std::chrono::milliseconds(kAcceptBackoffMs));
      self->backoff_.async_wait([self](beast::error_code wait_error) {
        if (!wait_error) self->Accept();
      });
    });
  }

 private:
  tcp::acceptor acceptor_;
  net::steady_timer backoff_;
  bool accept_failing_ = false;  ///< the last accept failed (said once until one succeeds)
  Hub& hub_;
  const std::string& page_;
};

/// Reads the events of an LCM log that another process is still writing: whole events only, from
/// where the last read stopped (run_recorder flushes every 100 ms, possibly mid-event).
class LogTail {
 public:
  explicit LogTail(std::string path) : path_(std::move(path)) {}

  /// Calls on_event(channel, timestamp_us, data, size) for every complete new event.
  template <typename F>
  void Poll(F&& on_event) {
    if (!file_.is_open()) {
      file_.open(path_, std::ios::binary);
      if (!file_.is_open()) return;  // not written yet
    }
    for (;;) {
      file_.clear();
      file_.seekg(offset_);
      unsigned char header[28];
      if (!file_.read(reinterpret_cast<char*>(header), sizeof header)) return;
      const uint32_t magic = Be32(header);
      if (magic != 0xEDA1DA01u) throw rbcp::InputError(path_ + ": not an LCM log (no event at byte " + std::to_string(offset_) + ")");
      const int64_t timestamp = static_cast<int64_t>(Be64(header + 12));
      const uint32_t channel_length = Be32(header + 20);
      const uint32_t data_length = Be32(header + 24);
      if (channel_length > 1024 || data_length > (1u << 28)) {
        throw rbcp::InputError(path_ + ": malformed event at byte " + std::to_string(offset_));
      }
      std::string channel(channel_length, '\0');
      data_.resize(data_length);
      if (!file_.read(channel.data(), channel_length) || !file_.read(reinterpret_cast<char*>(data_.data()), data_length)) {
        return;  // the rest of this event is not written yet
      }
      offset_ += static_cast<std::streamoff>(sizeof header + channel_length + data_length);
      on_event(channel, timestamp, data_.data(), data_length);
    }
  }

 private:
  static uint32_t Be32(const unsigned char* p) {
    return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
  }
  static uint64_t Be64(const unsigned char* p) { return (uint64_t{Be32(p)} << 32) | Be32(p + 4); }

  std::string path_;
  std::ifstream file_;
  std::streamoff offset_ = 0;
  std::vector<unsigned char> data_;
};

/// Moves this process (single-threaded so far) into the named network namespace (`ip netns`):
/// sockets made from here on are in it, those made before stay where they were.
void EnterNetworkNamespace(const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..") {
    throw rbcp::InputError("--lcm-netns: expected the name of a network namespace (ip netns list), got '" + name + "'");
  }
  const std::string path = "/run/netns/" + name;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw rbcp::InputError("--lcm-netns: no network namespace '" + name + "' (" + path + ": " + std::strerror(errno) + ")");
  const int rc = ::setns(fd, CLONE_NEWNET);
  const int error = errno;
  ::close(fd);
  if (rc != 0) throw rbcp::InputError("--lcm-netns: cannot enter the network namespace '" + name + "': " + std::strerror(error) + " (needs root)");
}

int64_t NowUs() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The pipeline's messages as LCM delivers them, handed to the hub whenever the LCM socket has one.
class LcmFeed {
 public:
  static constexpr int kQueueCapacity = 100000;  ///< received messages kept until handled

  LcmFeed(net::io_context& io, const std::string& lcm_url, Hub& hub) : lcm_(rbcp::transport::OpenLcm(lcm_url)) {
    lcm::Subscription* every_channel = lcm_->subscribeFunction(
        ".*",
        +[](const lcm::ReceiveBuffer* buffer, const std::string& channel, Hub* h) {
          h->OnMessage(channel, NowUs(), buffer->data, buffer->data_size);
        },
        &hub);
    // LCM keeps 30 received messages per subscription by default: one subscription to every
    // channel would lose a plan amid a burst of robot states whenever the bridge is busy.
    every_channel->setQueueCapacity(kQueueCapacity);
    socket_ = std::make_unique<net::posix::stream_descriptor>(io, ::dup(lcm_->getFileno()));
    Wait();
  }

 private:
  void Wait() {
    socket_->async_wait(net::posix::stream_descriptor::wait_read, [this](beast::error_code error) {
      if (error) return;
      while (lcm_->handleTimeout(0) > 0) {
      }
      Wait();
    });
  }

  std::unique_ptr<lcm::LCM> lcm_;
  std::unique_ptr<net::posix::stream_descriptor> socket_;  ///< a copy of the LCM socket, watched by the context
};

/// The pipeline's messages from a growing LCM log, read every 100 ms.
class LogFeed {
 public:
  LogFeed(net::io_context& io, const std::string& path, Hub& hub) : tail_(path), timer_(io), hub_(hub) { Poll(); }

 private:
  void Poll() {
    tail_.Poll([&](const std::string& channel, int64_t t, const void* data, unsigned size) {
      hub_.OnMessage(channel, t, data, size);
    });
    timer_.expires_after(std::chrono::milliseconds(100));
    timer_.async_wait([this](beast::error_code error) {
      if (!error) Poll();
    });
  }

  LogTail tail_;
  net::steady_timer timer_;
  Hub& hub_;
};

/// Stops the context on SIGINT or SIGTERM, or after max_runtime_s (0: never).
class StopConditions {
 public:
  StopConditions(net::io_context& io, double max_runtime_s) : signals_(io, SIGINT, SIGTERM), deadline_(io) {
    signals_.async_wait([&io](beast::error_code, int) { io.stop(); });
    if (max_runtime_s > 0) {
      deadline_.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(max_runtime_s)));
      deadline_.async_wait([&io](beast::error_code error) {
        if (!error) io.stop();
      });
    }
  }

 private:
  net::signal_set signals_;
  net::steady_timer deadline_;
};

/// The command line.
struct Options {
  rbcp::cli::CommonOptions common;
  int port = 8765;
  std::string page_path, follow_log, lcm_netns;
};

void AddOptions(CLI::App& app, Options& o) {
  rbcp::cli::AddCommonOptions(app, o.common);
  app.add_option("--port", o.port, "TCP port on 127.0.0.1 (0: any free port)")->capture_default_str()->check(CLI::Range(0, 65535));
  app.add_option("--page", o.page_path, "the page GET / returns (tools/view --live writes it)")->check(CLI::ExistingFile);
  app.add_option("--follow-log", o.follow_log,
                 "read the messages from this LCM log as it grows (e.g. build/logs/RUN/run.lcmlog while tools/launch "
                 "runs, from another network namespace) instead of subscribing on --lcm-url");
  app.add_option("--lcm-netns", o.lcm_netns,
                 "subscribe on --lcm-url inside this named network namespace (ip netns) while the page is served on\n"
                 "127.0.0.1 where the bridge started: a pipeline in a namespace followed from a browser outside it\n"
                 "(needs root)")
      ->excludes("--follow-log");
  app.description(
      "Forwards a running pipeline to web pages over a websocket on 127.0.0.1 (for tools/view --live):\n"
      "the LCM messages of the processes (on --lcm-url, or read from a growing LCM log with\n"
      "--follow-log) as compact JSON (docs/json_schema.md, live messages). GET / returns the page of\n"
      "--page; the websocket is at /ws. A page that connects late first gets what came before.\n"
      "Prints 'live_bridge: listening on http://127.0.0.1:PORT/' once it listens. Runs until SIGINT or\n"
      "SIGTERM (or --max-runtime). Exit status: 0 stopped, 2 bad input.");
}

/// The page GET / returns: the file's bytes, "" without one.
std::string ReadPage(const std::string& path) {
  if (path.empty()) return "";
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

/// A listener on 127.0.0.1:port (0: any free port); a port that cannot be had is bad input.
std::shared_ptr<Listener> Listen(net::io_context& io, int port, Hub& hub, const std::string& page) {
  try {
    return std::make_shared<Listener>(io, tcp::endpoint(net::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)),
                                      hub, page);
  } catch (const boost::system::system_error& e) {
    throw rbcp::InputError("cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + e.code().message());
  }
}

int Run(const Options& o) {
  const std::string page = ReadPage(o.page_path);
  const rbcp::RobotModel robot = rbcp::RobotModel::LoadDefault(o.common.config_dir);
  // The context outlives the hub: the pages' sockets in the hub are closed before it goes.
  net::io_context io;
  Hub hub(robot, o.common.quiet);
  const std::shared_ptr<Listener> listener = Listen(io, o.port, hub, page);
  listener->Accept();
  if (!o.lcm_netns.empty()) EnterNetworkNamespace(o.lcm_netns);
  std::optional<LcmFeed> lcm_feed;
  std::optional<LogFeed> log_feed;
  if (o.follow_log.empty()) {
    lcm_feed.emplace(io, o.common.lcm_url, hub);
  } else {
    log_feed.emplace(io, o.follow_log, hub);
  }
  const StopConditions stop(io, o.common.max_runtime_s);
  std::cerr << "live_bridge: listening on http://127.0.0.1:" << listener->Port() << "/ (websocket ws://127.0.0.1:"
            << listener->Port() << "/ws), "
            << (o.follow_log.empty() ? "LCM on '" + o.common.lcm_url + "'" + (o.lcm_netns.empty() ? "" : " in the network namespace " + o.lcm_netns)
                                     : "following " + o.follow_log) << std::endl;
  io.run();
  std::cerr << "live_bridge: stopped (" << hub.Malformed() << " malformed messages dropped)" << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main("live_bridge", argc, argv, AddOptions, Run); }
