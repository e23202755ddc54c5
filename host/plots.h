// Charts and contour drawings as SVG files, drawn by gnuplot (Debian: gnuplot-nox), for
// `mahost analyze --plots` (paper §4, Fig. 22-25) and `--layer-index` (Fig. 12-16).
//
// gnuplot runs as a child process on one script file with the data inline (gnuplot 5 data
// blocks), removed afterwards, so nothing is left behind but the SVG. Errors are the user's to
// fix and say how: gnuplot missing (install gnuplot-nox), a file that cannot be written, or
// gnuplot failing (its first error line) throw app::InputError naming the file.
#pragma once

#include <string>
#include <vector>

#include "app/analyze.h"  // geometry::Loop, as analyze's regions and footprints carry them

namespace host {

struct Series {
  std::string title;
  std::vector<double> x, y;
  // gnuplot style: "points pt 7 ps 0.4", "lines lw 2", "impulses lw 2", "steps".
  std::string style = "points pt 7 ps 0.4";
  std::string colour;  // "#1f77b4"; empty: gnuplot's next colour
};

struct Chart {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  double y_max = 0;  // > 0: the y axis runs from 0 to this (points above are left out)
};

// A line chart or scatter plot of the series, 900 x 500 px.
void write_chart_svg(const std::string& path, const Chart& chart);

struct Outline {
  std::string title;
  std::vector<geometry::Loop> loops;
  std::string colour = "#000000";
  double width = 1.5;
  bool dashed = false;
};

// Closed loops drawn to scale (equal axes, mm), one legend entry per outline, 900 x 900 px.
void write_outlines_svg(const std::string& path, const std::string& title,
                        const std::vector<Outline>& outlines);

// The script that would be sent to gnuplot (for tests and --plots debugging).
std::string chart_script(const std::string& path, const Chart& chart);
std::string outlines_script(const std::string& path, const std::string& title,
                            const std::vector<Outline>& outlines);

}  // namespace host
