// The HTTP side of `mahost serve`: OctoPrint's REST API (the subset the slicers use), mahost's
// own additions under /api/mahost/, file downloads, and the web page, on cpp-httplib.
//
// Every route is one entry of the table in http_api.cpp (method, path, handler). Around them:
// - the API key, required on every /api/ and /downloads/ request as the X-Api-Key header:
//   none is 401, a wrong one 403 (never a cookie, so a foreign page cannot act; the page
//   itself is static and needs no key to load);
// - limits checked before a body is read: an upload's announced size (413), a JSON body
//   of more than 64 KiB (413), a JSON request without a length (411);
// - every refusal answered as JSON {"error": "..."} with OctoPrint's status codes, logged on
//   stderr with the client's address, and no exception ever escapes to the client beyond a
//   500 with no detail.
// The handlers only read the session's snapshot and queue requests (printer_session.h); none
// of them talks to the printer.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

namespace httplib {
struct Request;
struct Response;
class ContentReader;
}  // namespace httplib

namespace host::serve {

class PrinterSession;
class FileStore;
class HttpServer;

struct ServeLimits {
  std::uint64_t max_upload = 512ull << 20;  // bytes of one uploaded file
  std::size_t max_json = 64 << 10;          // bytes of a JSON request body
  int max_streams = 16;                     // live-update streams open at once
};

class HttpApi {
 public:
  HttpApi(PrinterSession& session, FileStore& files, std::string api_key, ServeLimits limits,
          std::string version);

  // Installs the routes, the key check, the limits, the error answers and the log, and tells
  // the server which requests are always served (the printer's controls).
  void install(HttpServer& server);
  // Ends the live-update streams (at shutdown).
  void close() { closing_.store(true); }

  // Route handlers (public so the route table can name them).
  void get_version(const httplib::Request&, httplib::Response&);
  void get_server(const httplib::Request&, httplib::Response&);
  void get_settings(const httplib::Request&, httplib::Response&);
  void post_login(const httplib::Request&, httplib::Response&);
  void get_printer_profiles(const httplib::Request&, httplib::Response&);
  void get_connection(const httplib::Request&, httplib::Response&);
  void post_connection(const httplib::Request&, httplib::Response&);
  void get_files(const httplib::Request&, httplib::Response&);
  void get_file(const httplib::Request&, httplib::Response&);
  void post_file(const httplib::Request&, httplib::Response&);
  void delete_file(const httplib::Request&, httplib::Response&);
  void download(const httplib::Request&, httplib::Response&);
  void get_job(const httplib::Request&, httplib::Response&);
  void post_job(const httplib::Request&, httplib::Response&);
  void get_printer(const httplib::Request&, httplib::Response&);
  void get_tool(const httplib::Request&, httplib::Response&);
  void get_bed(const httplib::Request&, httplib::Response&);
  void post_command(const httplib::Request&, httplib::Response&);
  void get_status(const httplib::Request&, httplib::Response&);
  void get_events(const httplib::Request&, httplib::Response&);
  void get_layer(const httplib::Request&, httplib::Response&);
  void get_profiles(const httplib::Request&, httplib::Response&);
  void post_interrupted(const httplib::Request&, httplib::Response&);
  void post_stop(const httplib::Request&, httplib::Response&);
  void post_pause_at(const httplib::Request&, httplib::Response&);
  void upload(const httplib::Request&, httplib::Response&, const httplib::ContentReader&);

 private:
  PrinterSession& session_;
  FileStore& files_;
  std::string api_key_;
  ServeLimits limits_;
  std::string version_;
  std::atomic<bool> closing_{false};
  std::atomic<int> streams_{0};
};

}  // namespace host::serve
