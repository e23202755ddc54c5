// `mahost serve (--port P | --dry-run) [--listen 127.0.0.1:5000] [--files DIR] ...`: the printer
// on the network. An OctoPrint-compatible API (what PrusaSlicer's OctoPrint host type and
// Cura's OctoPrint plugin use) and a web page, served by this process, with the printer
// session behind them (host/serve/printer_session.h): the link kept open, one job at a time
// through printer::Job with its journal, pause and resume, STL uploads sliced here.
//
// It prints the URL to open on its first stdout line ("mahost serve: http://HOST:PORT/") and
// events and refusals on stderr. Ctrl-C (or SIGTERM) cancels a running print safely and
// exits; a second one stops the printer at once (M112).
#include <signal.h>
#include <sys/socket.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <httplib.h>

#include "app/profile_paths.h"
#include "host/cli_checks.h"
#include "host/commands.h"
#include "host/job_setup.h"
#include "host/serve/api_key.h"
#include "host/serve/file_store.h"
#include "host/serve/http_api.h"
#include "host/serve/http_server.h"
#include "host/serve/printer_session.h"
#include "printer/error.h"
#include "printer/profile.h"
#include "printer/serial_link.h"

namespace host {
namespace {

namespace fs = std::filesystem;

constexpr const char* kServeGroup = "Server";

struct ServeOptions {
  LinkOptions link;
  std::string listen = "127.0.0.1:5000";
  std::string files;
  std::string printer = printer::kDefaultPrinter;
  std::string material;
  std::vector<std::string> overrides;
  std::string time_scale = "1";
  bool time_scale_given = false;
  double max_upload_mib = 512;
  std::string record, printed_stl;
};

struct ListenAddress {
  std::string host;
  int port = 5000;
};

// "127.0.0.1:5000", "[::1]:5000", "0.0.0.0:80", or a port alone (on 127.0.0.1).
ListenAddress parse_listen(const std::string& text) {
  ListenAddress a;
  std::string port_text;
  if (text.find(':') == std::string::npos) {
    a.host = "127.0.0.1";
    port_text = text;
  } else if (text.front() == '[') {
    const auto close = text.find(']');
    if (close == std::string::npos || close + 1 >= text.size() || text[close + 1] != ':') {
      throw printer::ConfigError(fmt::format("--listen {}: write an IPv6 address as [::1]:5000", text));
    }
    a.host = text.substr(1, close - 1);
    port_text = text.substr(close + 2);
  } else {
    const auto colon = text.rfind(':');
    a.host = text.substr(0, colon);
    port_text = text.substr(colon + 1);
  }
  try {
    std::size_t used = 0;
    a.port = std::stoi(port_text, &used);
    if (used != port_text.size() || a.port < 0 || a.port > 65535) throw std::out_of_range("port");
  } catch (const std::exception&) {
    throw printer::ConfigError(fmt::format(
        "--listen {}: give HOST:PORT with a port from 0 to 65535 (0: any free port), e.g. 127.0.0.1:5000", text));
  }
  if (a.host.empty()) {
    throw printer::ConfigError(fmt::format(
        "--listen {}: give the address to listen on, e.g. 127.0.0.1:{} (this machine only) or "
        "0.0.0.0:{} (every network it is on)",
        text, a.port, a.port));
  }
  return a;
}

bool loopback(const std::string& host) {
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

std::string default_files_folder() {
  if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg != nullptr && xdg[0] == '/') {
    return std::string(xdg) + "/mahost/files";
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && home[0] == '/') {
    return std::string(home) + "/.local/share/mahost/files";
  }
  throw printer::ConfigError("neither XDG_DATA_HOME nor HOME is set: give the files folder with --files DIR");
}

// The options that need no file, no port and no profile, checked first; the address to listen on.
ListenAddress check_serve_options(const ServeOptions& options) {
  check_link_choice(options.link, "serve");
  if (options.time_scale_given && !options.link.dry_run) {
    throw printer::ConfigError("--time-scale: only a --dry-run printer's clock can be sped up");
  }
  if (!(options.max_upload_mib > 0)) throw printer::ConfigError("--max-upload: give a size in MiB above 0");
  const ListenAddress address = parse_listen(options.listen);
  if (!options.link.dry_run) printer::check_serial_port(options.link.port);
  return address;
}

printer::Profiles serve_profiles(const ServeOptions& options) {
  printer::ProfileRequest request;
  request.printer = options.printer;
  request.material = options.material;
  request.config_dir = app::profile_search_path();
  request.overrides = options.overrides;
  return printer::load_profiles(request);
}

serve::PrinterSession::Options session_options_for(const ServeOptions& options, const printer::Profiles& profiles) {
  serve::PrinterSession::Options session_options;
  session_options.link = options.link;
  session_options.link.time_scale = parse_time_scale(options.time_scale);
  session_options.profiles = profiles;
  session_options.baud = options.link.baud > 0 ? options.link.baud : profiles.printer.baud;
  session_options.record_path = options.record;
  session_options.printed_stl_path = options.printed_stl;
  return session_options;
}

// SIGINT and SIGTERM go to the watcher thread (watch_signals), not to whichever thread the
// kernel picks: blocked before any thread starts, so every thread inherits the mask. Returns
// the set blocked.
sigset_t block_stop_signals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  signal(SIGHUP, SIG_IGN);  // a print outlives the terminal that started it
  signal(SIGPIPE, SIG_IGN);
  return signals;
}

void configure_server(serve::HttpServer& server, const serve::ServeLimits& limits) {
  server.set_keep_alive_max_count(1000);
  // What the Keep-Alive header tells clients: the idle time after which the server closes.
  server.set_keep_alive_timeout(std::chrono::duration_cast<std::chrono::seconds>(server.limits().idle).count());
  server.set_payload_max_length(limits.max_upload + (1u << 20));
  // httplib writes a response's head and body apart: without this the body of a kept-alive
  // connection waits for the client's delayed ack (40 ms on Linux).
  server.set_tcp_nodelay(true);
}

// Binds the address and listens; the port bound (the one asked for, or the free one found for
// port 0). httplib's default lets a second server share the port (SO_REUSEPORT), splitting the
// requests between two printers: only SO_REUSEADDR here, so a port in use is an error. And a
// listening queue deeper than its 5, so a burst of new connections is not dropped (a client
// whose SYN is dropped waits a second before it tries again).
int bind_address(serve::HttpServer& server, const ListenAddress& address, const std::string& listen_text) {
  int listening = -1;
  server.set_socket_options([&listening](int sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    listening = sock;
  });
  const int port = address.port == 0 ? server.bind_to_any_port(address.host)
                                     : (server.bind_to_port(address.host, address.port) ? address.port : -1);
  if (port >= 0 && listening >= 0) ::listen(listening, 128);
  if (port < 0) {
    throw printer::ConfigError(fmt::format(
        "--listen {}: cannot listen there (another program on the port, or not an address of "
        "this machine); pick another with --listen HOST:PORT",
        listen_text));
  }
  return port;
}

// Starts the session and waits until the printer answered (or failed to), so a client that
// reads the address finds the printer operational, or says why not.
void connect_printer(serve::PrinterSession& session) {
  session.start();
  for (auto status = session.status(); status.connection == serve::Connection::connecting;) {
    status = session.wait_for_change(status.version, std::chrono::milliseconds(1000));
  }
}

// The key's origin and a warning for an address other machines reach, on stderr; the URL to
// open on stdout.
void announce(const ServeOptions& options, const ListenAddress& address, int port, const serve::ApiKey& key,
              const serve::FileStore& files) {
  const std::string shown_host = address.host.find(':') != std::string::npos ? "[" + address.host + "]" : address.host;
  if (key.created) {
    fmt::print(stderr, "API key: {} (made now, kept in {}; give it to the page and the slicers)\n", key.value,
               key.source);
  } else {
    fmt::print(stderr, "API key: from {}\n", key.source);
  }
  if (!loopback(address.host)) {
    fmt::print(stderr,
               "warning: listening on {}:{}, reachable from other machines: anyone who can reach it "
               "and has the API key can run the printer, and HTTP is not encrypted; use it on a "
               "network you trust\n",
               shown_host, port);
  }

  fmt::print("mahost serve: http://{}:{}/ ({}, files in {})\n", shown_host, port,
             options.link.dry_run ? "the simulated printer" : options.link.port, files.folder());
  std::fflush(stdout);
}

// The watcher thread's body: the first signal cancels a running print and shuts down, a second
// one stops the printer at once; once the session has finished, the API and the server stop.
// `listen_returned`: set by the main thread when the server's listen has returned.
void watch_signals(const sigset_t& signals, serve::PrinterSession& session, serve::HttpApi& api,
                   serve::HttpServer& server, const std::atomic<bool>& listen_returned) {
  int received = 0;
  while (!session.finished()) {
    timespec wait{0, 200'000'000};
    siginfo_t info{};
    if (sigtimedwait(&signals, &info, &wait) > 0) {
      ++received;
      const bool printing = session.status().job_active;
      if (received == 1 && printing) {
        fmt::print(stderr, "mahost serve: cancelling the print, then exiting (again: stop at once, M112)\n");
      }
      session.shut_down(received > 1);
    }
  }
  api.close();
  // httplib's stop() does nothing until listen_after_bind has begun its loop (is_running), and a
  // signal that comes as the address is announced can end the session before the main thread
  // gets there: the server would then listen on, and the process never exit.
  while (!server.is_running() && !listen_returned.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  server.stop();
}

void run_serve(const ServeOptions& options) {
  const ListenAddress address = check_serve_options(options);
  const printer::Profiles profiles = serve_profiles(options);
  const serve::ApiKey key = serve::load_api_key();
  serve::FileStore files(options.files.empty() ? default_files_folder() : options.files,
                         profiles.printer.motion, profiles.printer.filament_diameter);
  const serve::PrinterSession::Options session_options = session_options_for(options, profiles);
  const sigset_t signals = block_stop_signals();

  serve::PrinterSession session(session_options, files);
  serve::ServeLimits limits;
  limits.max_upload = static_cast<std::uint64_t>(options.max_upload_mib * 1048576.0);
  serve::HttpApi api(session, files, key.value, limits, MAHOST_VERSION);
  serve::HttpServer server(serve::ConnectionLimits{});
  configure_server(server, limits);
  api.install(server);
  const int port = bind_address(server, address, options.listen);
  connect_printer(session);
  announce(options, address, port, key, files);

  std::atomic<bool> listen_returned{false};
  std::thread watcher([&] { watch_signals(signals, session, api, server, listen_returned); });
  server.listen_after_bind();
  listen_returned.store(true);
  // listen returns when stopped (or when its socket failed): make sure the session ends too.
  session.shut_down(false);
  watcher.join();
  session.wait();
}

}  // namespace

void add_serve_command(CLI::App& app) {
  auto options = std::make_shared<ServeOptions>();
  auto* serve = app.add_subcommand(
      "serve", "Serve the printer on the network: an OctoPrint-compatible API and a web page");
  serve->footer(
      "Open the printed address in a browser and give it the API key. In PrusaSlicer: "
      "Physical printer, host type OctoPrint, the address and the API key; in Cura: the "
      "OctoPrint Connection plugin, the same. Every API call needs the key in the X-Api-Key "
      "header; it is made at the first start and kept in ~/.config/mahost/api-key (or taken "
      "from MAHOST_API_KEY). Ctrl-C cancels a running print and exits; again: stops at once.");
  add_link_options(*serve, options->link, "the printer profile's serial.baud",
                   "serve the in-process simulated printer instead of a port, at real speed unless "
                   "--time-scale says otherwise (default: off; give --port or --dry-run)");
  // An upload with lines that are not G-code is refused when it arrives, naming the line:
  // there is no file on the command line to leave lines out of.
  serve->remove_option(serve->get_option("--force"));
  serve->add_option("--listen", options->listen,
                    "address and port to listen on; 0.0.0.0:PORT is every network (then anyone "
                    "there with the key can print); port 0: any free one (default: 127.0.0.1:5000)")
      ->group(kServeGroup);
  serve->add_option("--files", options->files,
                    "the folder of uploaded files (default: $XDG_DATA_HOME/mahost/files, or "
                    "~/.local/share/mahost/files)")
      ->group(kServeGroup);
  serve->add_option("--max-upload", options->max_upload_mib, "the largest upload taken, MiB (default: 512)")
      ->check(number_in(0.001, 65536.0))
      ->group(kServeGroup);
  serve->add_option("--printer", options->printer,
                    fmt::format("the printer's profile: a name (up-plus-2, generic-marlin) or a "
                                ".toml path; uploaded STL files are sliced for it (default: {})",
                                printer::kDefaultPrinter))
      ->group(kServeGroup);
  serve->add_option("--material", options->material,
                    "the material profile STL uploads are sliced with (default: the printer's)")
      ->group(kServeGroup);
  serve->add_option("--set", options->overrides, "override a profile key, e.g. --set retraction.length=1.5")
      ->allow_extra_args(false)
      ->group(kServeGroup);
  serve->add_option("--time-scale", options->time_scale,
                    "the simulated printer's clock per wall clock: 1 = real time, N = N times "
                    "faster, max = no waiting (default: 1)")
      ->group(kDryRunGroup);
  serve->add_option("--record", options->record,
                    "write the simulated printer's record (commands, deposition; as mahost sim "
                    "--record) after each job and at exit")
      ->group(kDryRunGroup);
  serve->add_option("--printed-stl", options->printed_stl,
                    "write the part the simulated printer deposited, as STL, after each job and at exit")
      ->group(kDryRunGroup);
  serve->callback([options, serve] {
    options->time_scale_given = serve->count("--time-scale") > 0;
    if ((!options->record.empty() || !options->printed_stl.empty()) && !options->link.dry_run) {
      throw printer::ConfigError("--record, --printed-stl: only a --dry-run printer keeps a record");
    }
    run_serve(*options);
  });
}

}  // namespace host
