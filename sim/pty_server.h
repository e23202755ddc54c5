// The simulated printer on a pseudo-terminal, so that any host (ours, printcore, OctoPrint)
// can open it like a USB printer (`mahost sim`, DESIGN.md §4).
//
// A pty pair is opened in raw mode; hosts open the slave path (/dev/pts/N). The server holds
// only the master, so it sees when the last host closes the port (the master hangs up) and
// when one opens it again. A board with USB-serial resets when a host opens the port (DTR);
// so, by default, every open resets the firmware and it says `start` again, and a host that
// closes and reopens the port (printcore does on connect; a later `mahost resume` does) finds
// a freshly booted printer; reset_on_open = false models a board that does not reset (native
// USB) and keeps its state across opens. While no host has the port open, replies are lost.
//
// Time: the sim clock follows the wall clock times time_scale (1 = real time); time_scale 0
// runs every wait (booting, heating, moves, dwells) at once and follows the wall clock only
// while the firmware waits for the host. With baud > 0 bytes are paced both ways at 10 bits a byte:
// the server reads no faster than a UART at that rate would deliver (the rest waits in the
// kernel, as in a host's serial driver) and writes no faster either.
#pragma once

#include <atomic>
#include <functional>
#include <string>

#include "sim/printer.h"

namespace sim {

struct PtyOptions {
  double time_scale = 1;    // 0 = as fast as possible
  double baud = 0;          // 0 = no pacing
  bool reset_on_open = true;
  // Told when a host opens the port (true) and when the last one closes it (false), from the
  // serving thread: `mahost sim` says so, and a test can wait for it.
  std::function<void(bool opened)> on_session;
};

class PtyServer {
 public:
  // Opens the pty pair. Throws printer::LinkError when no pseudo-terminal can be had.
  PtyServer(Config config, PtyOptions options);
  ~PtyServer();
  PtyServer(const PtyServer&) = delete;
  PtyServer& operator=(const PtyServer&) = delete;

  // The path hosts open, e.g. "/dev/pts/5".
  const std::string& path() const { return path_; }

  // Serves until `stop` is set (checked at least every 50 ms and when a signal interrupts)
  // or a disconnect fault fires (the master is then closed: hosts see the port vanish).
  void serve(const std::atomic<bool>& stop);

  const Printer& printer() const { return printer_; }
  Printer& printer() { return printer_; }
  // How many times a host opened the port.
  int opens() const { return opens_; }

 private:
  // One serve() call's clocks, byte budgets and replies not yet written (pty_server.cpp).
  struct Session;
  // serve()'s steps, once a turn:
  void follow_host(Session& s);      // a host opened the port (reset) or the last one left
  void catch_up(Session& s);         // the sim clock to the wall clock (or ahead at full speed)
  void read_host(Session& s);        // bytes from the host, no faster than a UART brings them
  void run_ahead(Session& s);        // full speed: what the firmware does without the host
  void write_host(Session& s);       // replies to the host, paced likewise
  void sleep_until_due(Session& s);  // until input, a firmware event, a byte slot or 50 ms
  void close_master();

  Printer printer_;
  PtyOptions options_;
  int master_ = -1;
  std::string path_;
  int opens_ = 0;
};

}  // namespace sim
