// The web page's files (host/serve/web/), embedded into the binary at build time by
// host/serve/embed_web.cmake: the page needs nothing from the network, no CDN, no build step.
#pragma once

#include <string_view>

namespace host::serve {

struct WebAsset {
  std::string_view path;          // as requested: "/", "/app.js", "/style.css"
  std::string_view content_type;  // "text/html; charset=utf-8", ...
  std::string_view body;
};

// The asset served at `path`, or null.
const WebAsset* find_web_asset(std::string_view path);

}  // namespace host::serve
