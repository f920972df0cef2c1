#include "bench/svg_chart.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace humandyn::bench {

namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

// "1e-6", "10", "1000": the label of decade 10^e.
std::string decade_label(int e) {
  if (e >= 0 && e <= 4) {
    char b[16];
    std::snprintf(b, sizeof b, "%.0f", std::pow(10.0, e));
    return b;
  }
  return "1e" + std::to_string(e);
}

}  // namespace

std::vector<std::size_t> pareto_front(const std::vector<ChartPoint>& points) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return points[a].x < points[b].x || (points[a].x == points[b].x && points[a].y < points[b].y);
  });
  // walking by increasing x, a point is on the front when it is more accurate than every faster one
  std::vector<std::size_t> front;
  double best_y = std::numeric_limits<double>::infinity();
  for (std::size_t i : order)
    if (points[i].y < best_y) {
      front.push_back(i);
      best_y = points[i].y;
    }
  return front;
}

std::string render_svg(const Chart& chart) {
  const double W = 860, H = 560, left = 90, right = 250, top = 50, bottom = 70;
  const double pw = W - left - right, ph = H - top - bottom;

  // the decades spanned by every point
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  const auto clamp_y = [&](double y) { return std::max(y, chart.y_floor); };
  for (const auto& s : chart.series)
    for (const auto& p : s.points) {
      if (!(p.x > 0) || !std::isfinite(p.x) || !std::isfinite(p.y)) continue;
      xmin = std::min(xmin, p.x);
      xmax = std::max(xmax, p.x);
      ymin = std::min(ymin, clamp_y(p.y));
      ymax = std::max(ymax, clamp_y(p.y));
    }
  if (xmin > xmax) xmin = 1, xmax = 10, ymin = 1, ymax = 10;
  const int ex0 = int(std::floor(std::log10(xmin))), ex1 = std::max(ex0 + 1, int(std::ceil(std::log10(xmax))));
  const int ey0 = int(std::floor(std::log10(ymin))), ey1 = std::max(ey0 + 1, int(std::ceil(std::log10(ymax))));
  const auto X = [&](double x) { return left + pw * (std::log10(x) - ex0) / (ex1 - ex0); };
  const auto Y = [&](double y) { return top + ph * (1 - (std::log10(clamp_y(y)) - ey0) / (ey1 - ey0)); };

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W << ' '
    << H << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << fmt(left + pw / 2) << "\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">" << escape(chart.title)
    << "</text>\n";

  // grid: a line per decade, fainter lines at 2..9 times it
  const int ystep = std::max(1, (ey1 - ey0 + 9) / 10);
  for (int e = ex0; e <= ex1; ++e) {
    const double x = X(std::pow(10.0, e));
    o << "<line x1=\"" << fmt(x) << "\" y1=\"" << top << "\" x2=\"" << fmt(x) << "\" y2=\"" << top + ph
      << "\" stroke=\"#ccc\"/>\n";
    o << "<text x=\"" << fmt(x) << "\" y=\"" << fmt(top + ph + 18) << "\" text-anchor=\"middle\">" << decade_label(e)
      << "</text>\n";
    if (e < ex1)
      for (int m = 2; m <= 9; ++m) {
        const double xm = X(m * std::pow(10.0, e));
        o << "<line x1=\"" << fmt(xm) << "\" y1=\"" << top << "\" x2=\"" << fmt(xm) << "\" y2=\"" << top + ph
          << "\" stroke=\"#eee\"/>\n";
      }
  }
  for (int e = ey0; e <= ey1; ++e) {
    const double y = Y(std::pow(10.0, e));
    o << "<line x1=\"" << left << "\" y1=\"" << fmt(y) << "\" x2=\"" << left + pw << "\" y2=\"" << fmt(y)
      << "\" stroke=\"" << ((e - ey0) % ystep == 0 ? "#ccc" : "#eee") << "\"/>\n";
    if ((e - ey0) % ystep == 0)
      o << "<text x=\"" << fmt(left - 6) << "\" y=\"" << fmt(y + 4) << "\" text-anchor=\"end\">" << decade_label(e)
        << "</text>\n";
  }
  o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
    << "\" fill=\"none\" stroke=\"black\"/>\n";
  o << "<text x=\"" << fmt(left + pw / 2) << "\" y=\"" << fmt(H - 25) << "\" text-anchor=\"middle\">"
    << escape(chart.x_label) << "</text>\n";
  o << "<text transform=\"translate(22," << fmt(top + ph / 2) << ") rotate(-90)\" text-anchor=\"middle\">"
    << escape(chart.y_label) << "</text>\n";

  // series: Pareto front, connecting line, markers and labels
  for (const auto& s : chart.series) {
    if (s.pareto) {
      const auto front = pareto_front(s.points);
      if (!front.empty()) {
        std::ostringstream path;
        for (std::size_t k = 0; k < front.size(); ++k) {
          const auto& p = s.points[front[k]];
          if (k == 0) path << 'M' << fmt(X(p.x)) << ',' << fmt(Y(p.y));
          else path << " H" << fmt(X(p.x)) << " V" << fmt(Y(p.y));
        }
        path << " H" << fmt(left + pw);
        o << "<path d=\"" << path.str() << "\" fill=\"none\" stroke=\"" << s.color
          << "\" stroke-width=\"1.5\" stroke-dasharray=\"6,4\" opacity=\"0.7\"/>\n";
      }
    }
    if (s.connect && s.points.size() > 1) {
      o << "<polyline fill=\"none\" stroke=\"" << s.color << "\" stroke-width=\"1.5\""
        << (s.dashed ? " stroke-dasharray=\"5,3\"" : "") << " points=\"";
      for (const auto& p : s.points) o << fmt(X(p.x)) << ',' << fmt(Y(p.y)) << ' ';
      o << "\"/>\n";
    }
    for (const auto& p : s.points) {
      if (!(p.x > 0) || !std::isfinite(p.y)) continue;
      o << "<circle cx=\"" << fmt(X(p.x)) << "\" cy=\"" << fmt(Y(p.y)) << "\" r=\"4\" "
        << (s.hollow ? "fill=\"white\" stroke=\"" + s.color + "\" stroke-width=\"1.5\"" : "fill=\"" + s.color + "\"")
        << "/>\n";
      if (!p.label.empty())
        o << "<text x=\"" << fmt(X(p.x) + 7) << "\" y=\"" << fmt(Y(p.y) - 5) << "\" font-size=\"10\" fill=\"#333\">"
          << escape(p.label) << "</text>\n";
    }
  }

  // legend
  double ly = top + 10;
  for (const auto& s : chart.series) {
    const double lx = left + pw + 20;
    o << "<circle cx=\"" << fmt(lx) << "\" cy=\"" << fmt(ly) << "\" r=\"4\" "
      << (s.hollow ? "fill=\"white\" stroke=\"" + s.color + "\" stroke-width=\"1.5\"" : "fill=\"" + s.color + "\"")
      << "/>\n";
    o << "<text x=\"" << fmt(lx + 10) << "\" y=\"" << fmt(ly + 4) << "\">" << escape(s.name) << "</text>\n";
    ly += 18;
    if (s.pareto) {
      o << "<line x1=\"" << fmt(lx - 6) << "\" y1=\"" << fmt(ly) << "\" x2=\"" << fmt(lx + 6) << "\" y2=\"" << fmt(ly)
        << "\" stroke=\"" << s.color << "\" stroke-dasharray=\"6,4\"/>\n";
      o << "<text x=\"" << fmt(lx + 10) << "\" y=\"" << fmt(ly + 4) << "\">Pareto front</text>\n";
      ly += 18;
    }
  }
  o << "</svg>\n";
  return o.str();
}

void write_svg(const Chart& chart, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << render_svg(chart);
  if (!f) throw std::runtime_error("cannot write " + path);
}

}  // namespace humandyn::bench
