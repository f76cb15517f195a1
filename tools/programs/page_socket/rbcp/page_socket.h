#pragma once
// What live_bridge accepts from a page's connection (an HTTP request, then websocket frames) and
// the bounds that keep a connection's memory small whatever a client sends. live_bridge serves
// with these; the websocket_frames fuzz target (modules/fuzz) reads arbitrary bytes with them.
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <cstddef>
#include <string>

namespace rbcp::live_bridge {

/// The largest HTTP request header a connection may send [bytes].
constexpr std::size_t kMaxRequestHeaderBytes = 8192;
/// The largest HTTP request body [bytes]: the bridge serves GET only.
constexpr std::size_t kMaxRequestBodyBytes = 1024;
/// The largest message a page may send [bytes]: it has nothing to say, so a large or unfinished
/// frame is cut short instead of held (a page's memory stays bounded).
constexpr std::size_t kMaxPageMessageBytes = 4096;

/// A parser of one HTTP request with the bounds above; a longer request is an error.
inline void BoundRequest(boost::beast::http::request_parser<boost::beast::http::string_body>& parser) {
  parser.header_limit(kMaxRequestHeaderBytes);
  parser.body_limit(kMaxRequestBodyBytes);
}

/// The server side of a page's websocket: text messages out, at most kMaxPageMessageBytes in,
/// Beast's suggested server timeouts (a silent or half-open page is dropped).
template <class NextLayer>
void ConfigurePageSocket(boost::beast::websocket::stream<NextLayer>& ws) {
  namespace websocket = boost::beast::websocket;
  ws.set_option(websocket::stream_base::timeout::suggested(boost::beast::role_type::server));
  ws.read_message_max(kMaxPageMessageBytes);
  ws.text(true);
}

/// Origins allowed to open the websocket: a page from disk, or one the bridge served on `port`.
inline bool AllowedOrigin(const std::string& origin, unsigned short port) {
  const std::string p = ":" + std::to_string(port);
  return origin.empty() || origin == "null" || origin.rfind("file://", 0) == 0 || origin == "http://127.0.0.1" + p ||
         origin == "http://localhost" + p;
}

}  // namespace rbcp::live_bridge
