#include "host/plots.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include <fmt/core.h>
#include <fmt/format.h>

#include "app/error.h"

namespace host {

namespace {

// gnuplot strings in single quotes: a quote is doubled.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += "''";
    else if (c != '\n') out += c;
  }
  return out + "'";
}

std::string number(double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : "NaN"; }

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = dirs.find(':', start);
    const std::string dir = dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!dir.empty() && access((dir + "/" + program).c_str(), X_OK) == 0) return true;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return false;
}

// gnuplot on PATH and `path` writable, or InputError saying what to do.
void check_can_plot(const std::string& path) {
  if (!on_path("gnuplot")) {
    throw app::InputError(fmt::format(
        "{}: drawing plots needs gnuplot, which is not on PATH (install it: apt install "
        "gnuplot-nox), or leave out --plots/--layer-index",
        path));
  }
  // Fail early, in our words, when the file cannot be written at all.
  std::ofstream probe(path, std::ios::app);
  if (!probe) {
    throw app::InputError(fmt::format("{}: cannot write the plot here ({}); give a "
                                      "directory you can write to with --plots",
                                      path, std::strerror(errno)));
  }
}

// The script in a temporary file (in $TMPDIR, else /tmp), its path; the caller removes it.
// A file rather than a pipe: gnuplot dying half-way through a pipe would kill us with SIGPIPE.
std::string write_script_file(const std::string& script) {
  const char* tmp = std::getenv("TMPDIR");
  std::string script_path = std::string(tmp && *tmp ? tmp : "/tmp") + "/mahost-plot-XXXXXX";
  const int fd = mkstemp(script_path.data());
  if (fd < 0) throw std::runtime_error("cannot create a temporary file for gnuplot");
  const char* data = script.data();
  std::size_t left = script.size();
  while (left > 0) {
    const ssize_t n = write(fd, data, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      close(fd);
      unlink(script_path.c_str());
      throw std::runtime_error("cannot write a temporary file for gnuplot");
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  close(fd);
  return script_path;
}

struct GnuplotRun {
  bool ok = false;
  std::string said;  // its stderr
};

// Runs gnuplot on the script file, its stdin and stdout /dev/null.
GnuplotRun run_script(const std::string& script_path) {
  int errors[2];
  if (pipe(errors) != 0) throw std::runtime_error("pipe() failed");
  const pid_t child = fork();
  if (child < 0) throw std::runtime_error("fork() failed");
  if (child == 0) {
    dup2(errors[1], STDERR_FILENO);
    const int null = ::open("/dev/null", O_RDWR);
    if (null >= 0) {
      dup2(null, STDOUT_FILENO);
      dup2(null, STDIN_FILENO);
    }
    close(errors[0]);
    execlp("gnuplot", "gnuplot", script_path.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(errors[1]);
  GnuplotRun run;
  char buffer[4096];
  for (ssize_t n; (n = read(errors[0], buffer, sizeof buffer)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    run.said.append(buffer, static_cast<std::size_t>(n));
  }
  close(errors[0]);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  run.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  return run;
}

// The line of gnuplot's stderr that says what went wrong: the first naming an error, else
// the last that is more than its caret marks.
std::string first_error_line(const std::string& said) {
  std::string first;
  for (std::size_t p = 0; p < said.size();) {
    const std::size_t e = said.find('\n', p);
    std::string line = said.substr(p, e == std::string::npos ? std::string::npos : e - p);
    if (line.find_first_not_of(" ^") != std::string::npos) first = line;
    if (line.find("error") != std::string::npos || line.find("rror") != std::string::npos) {
      first = line;
      break;
    }
    if (e == std::string::npos) break;
    p = e + 1;
  }
  return first;
}

// Runs gnuplot on the script; throws InputError naming `path` if anything goes wrong.
void run_gnuplot(const std::string& path, const std::string& script) {
  check_can_plot(path);
  struct Removed {  // on every way out, a failed fork() too
    std::string path;
    ~Removed() { unlink(path.c_str()); }
  } script_file{write_script_file(script)};
  const GnuplotRun run = run_script(script_file.path);
  if (!run.ok) {
    const std::string first = first_error_line(run.said);
    throw app::InputError(fmt::format("{}: gnuplot could not draw the plot: {}", path,
                                      first.empty() ? "it exited with an error" : first));
  }
}

}  // namespace

std::string chart_script(const std::string& path, const Chart& chart) {
  std::string s;
  s += fmt::format("set terminal svg size 900,500 dynamic enhanced font 'sans,12' background '#ffffff'\n");
  s += fmt::format("set output {}\n", quoted(path));
  s += fmt::format("set title {} noenhanced\n", quoted(chart.title));
  s += fmt::format("set xlabel {} noenhanced\nset ylabel {} noenhanced\n", quoted(chart.x_label),
                   quoted(chart.y_label));
  s += "set grid\nset key outside right top noenhanced\nset datafile missing 'NaN'\n";
  if (chart.y_max > 0) s += fmt::format("set yrange [0:{}]\n", number(chart.y_max));
  for (std::size_t i = 0; i < chart.series.size(); ++i) {
    s += fmt::format("$series{} << EOD\n", i);
    const Series& series = chart.series[i];
    for (std::size_t k = 0; k < series.x.size() && k < series.y.size(); ++k)
      s += number(series.x[k]) + " " + number(series.y[k]) + "\n";
    if (series.x.empty()) s += "NaN NaN\n";  // gnuplot refuses an empty block
    s += "EOD\n";
  }
  s += "plot ";
  for (std::size_t i = 0; i < chart.series.size(); ++i) {
    const Series& series = chart.series[i];
    if (i) s += ", \\\n     ";
    s += fmt::format("$series{} using 1:2 with {}{} title {}", i, series.style,
                     series.colour.empty() ? "" : fmt::format(" lc rgb {}", quoted(series.colour)),
                     quoted(series.title));
  }
  if (chart.series.empty()) s += "NaN notitle";
  s += "\nunset output\n";
  return s;
}

std::string outlines_script(const std::string& path, const std::string& title,
                            const std::vector<Outline>& outlines) {
  std::string s;
  s += "set terminal svg size 900,900 dynamic enhanced font 'sans,12' background '#ffffff'\n";
  s += fmt::format("set output {}\n", quoted(path));
  s += fmt::format("set title {} noenhanced\n", quoted(title));
  s += "set size ratio -1\nset grid\nset xlabel 'x, mm'\nset ylabel 'y, mm'\n";
  s += "set key outside right top noenhanced\n";
  for (std::size_t i = 0; i < outlines.size(); ++i) {
    s += fmt::format("$outline{} << EOD\n", i);
    bool any = false;
    for (const geometry::Loop& loop : outlines[i].loops) {
      if (loop.empty()) continue;
      for (geometry::Vec2 p : loop) s += number(p.x) + " " + number(p.y) + "\n";
      s += number(loop[0].x) + " " + number(loop[0].y) + "\n\n";  // closed, then a break
      any = true;
    }
    if (!any) s += "NaN NaN\n";
    s += "EOD\n";
  }
  s += "plot ";
  for (std::size_t i = 0; i < outlines.size(); ++i) {
    const Outline& o = outlines[i];
    if (i) s += ", \\\n     ";
    s += fmt::format("$outline{} using 1:2 with lines lw {} lc rgb {}{} title {}", i,
                     number(o.width), quoted(o.colour), o.dashed ? " dt 2" : "", quoted(o.title));
  }
  if (outlines.empty()) s += "NaN notitle";
  s += "\nunset output\n";
  return s;
}

void write_chart_svg(const std::string& path, const Chart& chart) {
  run_gnuplot(path, chart_script(path, chart));
}

void write_outlines_svg(const std::string& path, const std::string& title,
                        const std::vector<Outline>& outlines) {
  run_gnuplot(path, outlines_script(path, title, outlines));
}

}  // namespace host
