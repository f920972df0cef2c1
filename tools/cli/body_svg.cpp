#include "cli/body_svg.hpp"

#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/data.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace humandyn::cli {

namespace {

constexpr double scale = 320;       // px per metre
constexpr double char_width = 6.7;  // px per character of the 11 px monospace labels
constexpr double line_height = 13;  // px per label line
constexpr double margin = 16;       // px around each view
constexpr double column_gap = 28;   // px between a label column and the body

std::string escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// A torque as the labels print it: exact zeros as 0, anything else with two decimals.
std::string torque_text(double tau) { return tau == 0 ? std::string("0") : fmt::format("{:.2f}", tau); }

// One way of looking at the body: which world axis runs to the screen's right, and which axis points
// towards the viewer (to draw far segments first).
struct ViewSpec {
  const char* caption;
  const char* across;  // the axis to the right, in words
  int h_axis;          // world axis to the right on screen (z is always up)
  int toward_viewer;   // world axis pointing at the viewer
  double toward_sign;
};

const ViewSpec front_view{"front view (y-z plane), seen from ahead: the body's left on the right", "y, left", 1, 0, +1};
const ViewSpec side_view{"side view (x-z plane), seen from the body's right: forward to the right", "x, forward", 0, 1,
                         -1};

struct Segment {
  Eigen::Vector3d a, b;
  bool massive;
};

struct Marker {
  Eigen::Vector3d p;
  int joint;
};

// Everything one view needs, in world coordinates.
struct Scene {
  std::vector<Segment> segments;
  std::vector<Marker> markers;
  Eigen::Vector3d base, base_com, com;
  std::vector<std::string> label_of_joint;
  double centre_y = 0;  // the body's middle, to colour left and right
};

// A cluster of joints drawn at the same spot, and where its label goes.
struct Callout {
  double x = 0, y = 0;  // the marker on screen
  std::vector<std::string> lines;
  bool right = false;  // label column
  double top = 0;      // label's top on screen
};

class ViewRenderer {
 public:
  ViewRenderer(const Scene& scene, const ViewSpec& spec, double x0, double y0) : scene_(scene), spec_(spec) {
    // bounds of everything drawn, in the view's plane
    hmin_ = vmin_ = 1e300;
    hmax_ = vmax_ = -1e300;
    const auto grow = [&](const Eigen::Vector3d& p) {
      hmin_ = std::min(hmin_, p[spec_.h_axis]);
      hmax_ = std::max(hmax_, p[spec_.h_axis]);
      vmin_ = std::min(vmin_, p.z());
      vmax_ = std::max(vmax_, p.z());
    };
    for (const auto& s : scene_.segments) grow(s.a), grow(s.b);
    for (const auto& m : scene_.markers) grow(m.p);
    grow(scene_.base), grow(scene_.base_com), grow(scene_.com);
    vmin_ = std::min(vmin_, 0.0);  // keep the z = 0 line in view

    // the view's frame: label column, body, label column; the columns as wide as the longest label
    std::size_t widest = 8;
    for (const auto& label : scene_.label_of_joint) widest = std::max(widest, label.size());
    column_width_ = double(widest) * char_width + 6;
    x0_ = x0;
    y0_ = y0;
    body_x0_ = x0_ + margin + column_width_ + column_gap;
    body_width_ = std::max((hmax_ - hmin_) * scale, 60.0);
    width_ = 2 * (margin + column_width_ + column_gap) + body_width_;
    const double caption_width = 7.6 * double(std::string(spec_.caption).size()) + 2 * margin;  // 12 px bold
    if (width_ < caption_width) {  // widen the body's strip so that the caption fits
      body_x0_ += (caption_width - width_) / 2;
      width_ = caption_width;
    }
    body_top_ = y0_ + 40;

    // clusters of markers at the same screen spot, one callout each
    for (const auto& m : scene_.markers) {
      const double x = hx(m.p), y = vy(m.p);
      Callout* c = nullptr;
      for (auto& k : callouts_)
        if (std::abs(k.x - x) < 2 && std::abs(k.y - y) < 2) c = &k;
      if (!c) {
        callouts_.push_back({x, y, {}, false, 0});
        c = &callouts_.back();
      }
      c->lines.push_back(scene_.label_of_joint[std::size_t(m.joint)]);
    }
    layout_callouts();
  }

  double width() const { return width_; }
  double height() const { return height_; }

  void draw(std::string& svg) const {
    const auto out = std::back_inserter(svg);
    const double cx = x0_ + width_ / 2;
    fmt::format_to(
        out, "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\" font-size=\"12\" font-weight=\"bold\">{}</text>\n",
        cx, y0_ + 14, escape(spec_.caption));

    // the z = 0 line
    const double y_ground = vy(Eigen::Vector3d::Zero());
    fmt::format_to(
        out,
        "<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#a0aec0\" stroke-dasharray=\"4 3\"/>\n",
        body_x0_ - column_gap / 2, y_ground, body_x0_ + body_width_ + column_gap / 2, y_ground);
    fmt::format_to(
        out, "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"end\" font-size=\"10\" fill=\"#718096\">z = 0</text>\n",
        body_x0_ + body_width_ + column_gap / 2, y_ground + 12);

    // the links, far ones first
    std::vector<const Segment*> order;
    for (const auto& s : scene_.segments) order.push_back(&s);
    std::stable_sort(order.begin(), order.end(),
                     [&](const Segment* a, const Segment* b) { return depth(a->a + a->b) < depth(b->a + b->b); });
    for (const Segment* s : order) {
      const double y_mid = 0.5 * (s->a.y() + s->b.y());
      const char* colour = y_mid > scene_.centre_y + 0.03   ? "#2b6cb0"   // left: blue
                           : y_mid < scene_.centre_y - 0.03 ? "#c53030"   // right: red
                                                            : "#2d3748";  // middle
      fmt::format_to(out,
                     "<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"{}\" stroke-width=\"{}\" "
                     "stroke-linecap=\"round\" stroke-opacity=\"0.85\"/>\n",
                     hx(s->a), vy(s->a), hx(s->b), vy(s->b), colour, s->massive ? 6 : 3);
    }

    // the base (fixed to the world) and its body
    fmt::format_to(
        out,
        "<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#4a5568\" stroke-width=\"6\" "
        "stroke-linecap=\"round\"/>\n",
        hx(scene_.base), vy(scene_.base), hx(scene_.base_com), vy(scene_.base_com));
    fmt::format_to(out, "<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"10\" height=\"10\" fill=\"#4a5568\"/>\n",
                   hx(scene_.base) - 5, vy(scene_.base) - 5);

    // the whole body's centre of mass
    const double mx = hx(scene_.com), my = vy(scene_.com);
    fmt::format_to(
        out, "<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"6\" fill=\"#fefcbf\" stroke=\"#744210\" stroke-width=\"1.5\"/>\n",
        mx, my);
    fmt::format_to(out, "<path d=\"M{:.1f} {:.1f}h12M{:.1f} {:.1f}v12\" stroke=\"#744210\" stroke-width=\"1.2\"/>\n",
                   mx - 6, my, mx, my - 6);
    fmt::format_to(out, "<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"10\" fill=\"#744210\">CoM</text>\n", mx + 8,
                   my + 4);

    // joints, leader lines and labels
    for (const auto& c : callouts_) {
      const double anchor_x = c.right ? x0_ + width_ - margin - column_width_ : x0_ + margin + column_width_;
      const double anchor_y = c.top + line_height / 2 + 0.5 * line_height * double(c.lines.size() - 1);
      fmt::format_to(out,
                     "<polyline points=\"{:.1f},{:.1f} {:.1f},{:.1f} {:.1f},{:.1f}\" fill=\"none\" stroke=\"#a0aec0\" "
                     "stroke-width=\"0.8\"/>\n",
                     c.x, c.y, anchor_x + (c.right ? -6 : 6), anchor_y, anchor_x, anchor_y);
    }
    for (const auto& c : callouts_)
      fmt::format_to(
          out, "<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"4\" fill=\"white\" stroke=\"#1a202c\" stroke-width=\"1.5\"/>\n",
          c.x, c.y);
    for (const auto& c : callouts_) {
      const double tx = c.right ? x0_ + width_ - margin - column_width_ + 2 : x0_ + margin + column_width_ - 2;
      for (std::size_t k = 0; k < c.lines.size(); ++k)
        fmt::format_to(out, "<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"11\" text-anchor=\"{}\">{}</text>\n", tx,
                       c.top + line_height * double(k + 1) - 3, c.right ? "start" : "end", escape(c.lines[k]));
    }

    // which way is which
    const double ax = x0_ + margin + 6, ay = y0_ + height_ - 14;
    fmt::format_to(
        out,
        "<path d=\"M{:.1f} {:.1f}h30M{:.1f} {:.1f}v-30\" stroke=\"#1a202c\" stroke-width=\"1.2\" fill=\"none\"/>\n", ax,
        ay, ax, ay);
    fmt::format_to(out, "<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"10\">{}</text>\n", ax + 34, ay + 4,
                   escape(spec_.across));
    fmt::format_to(out, "<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"10\">z, up</text>\n", ax - 4, ay - 34);
  }

 private:
  double hx(const Eigen::Vector3d& p) const { return body_x0_ + (p[spec_.h_axis] - hmin_) * scale; }
  double vy(const Eigen::Vector3d& p) const { return body_top_ + (vmax_ - p.z()) * scale; }
  double depth(const Eigen::Vector3d& p) const { return spec_.toward_sign * p[spec_.toward_viewer]; }

  // Labels left of the body for joints on its left half of the screen, right for the others (the
  // middle ones go where there are fewer), each column stacked top-down without overlaps.
  void layout_callouts() {
    const double mid = body_x0_ + body_width_ / 2;
    std::size_t lines_left = 0, lines_right = 0;
    std::vector<Callout*> middle;
    for (auto& c : callouts_) {
      if (c.x < mid - 1) {
        c.right = false;
        lines_left += c.lines.size();
      } else if (c.x > mid + 1) {
        c.right = true;
        lines_right += c.lines.size();
      } else {
        middle.push_back(&c);
      }
    }
    for (Callout* c : middle) {
      c->right = lines_right < lines_left;
      (c->right ? lines_right : lines_left) += c->lines.size();
    }
    double bottom = body_top_ + (vmax_ - vmin_) * scale;
    for (const bool right : {false, true}) {
      std::vector<Callout*> column;
      for (auto& c : callouts_)
        if (c.right == right) column.push_back(&c);
      std::sort(column.begin(), column.end(), [](const Callout* a, const Callout* b) { return a->y < b->y; });
      double next_free = body_top_ - 20;
      for (Callout* c : column) {
        const double h = line_height * double(c->lines.size());
        c->top = std::max(c->y - h / 2, next_free);
        next_free = c->top + h + 5;
      }
      bottom = std::max(bottom, next_free);
    }
    height_ = bottom - y0_ + 50;
  }

  const Scene& scene_;
  ViewSpec spec_;
  std::vector<Callout> callouts_;
  double hmin_, hmax_, vmin_, vmax_;
  double x0_ = 0, y0_ = 0, body_x0_ = 0, body_width_ = 0, body_top_ = 0, width_ = 0, height_ = 0;
  double column_width_ = 0;
};

// Where a joint's dot goes: on its axis, at its parent frame's origin; where several joints share that
// origin (a branch point), at the point of the axis nearest to the joint's own link frame instead, so
// that e.g. both shoulders do not sit on the neck.
Scene build_scene(const AnyModel<double>& model, const Data<AnyModel<double>>& data, const Eigen::VectorXd& tau) {
  Scene scene;
  const auto& d = model.description();
  const int n = model.size();
  scene.base = model.base_pose().p;
  scene.base_com = model.base_pose() * d.base_body.com;
  scene.com = data.com;

  std::vector<int> children(std::size_t(n + 1), 0);  // [0]: the base
  // children[p + 1]: how many joints hang from link p (index 0: the base)
  const auto slot = [](int parent) { return static_cast<std::size_t>(parent) + 1; };
  for (int i = 0; i < n; ++i) ++children[slot(model.joint(i).parent)];

  double y_sum = scene.base.y();
  for (int i = 0; i < n; ++i) {
    const auto& j = model.joint(i);
    Pose<double> axis_frame = j.parent < 0 ? model.base_pose() : data.oMi[std::size_t(j.parent)];
    if (j.mounted) axis_frame = axis_frame * Pose<double>{j.mount_R, j.mount_p};
    const Eigen::Vector3d origin = data.oMi[std::size_t(i)].p;
    const Eigen::Vector3d parent_origin = j.parent < 0 ? model.base_pose().p : data.oMi[std::size_t(j.parent)].p;
    if ((origin - parent_origin).norm() > 1e-9) scene.segments.push_back({parent_origin, origin, j.mass > 0});

    Eigen::Vector3d at = axis_frame.p;
    if (children[slot(j.parent)] > 1) {
      const Eigen::Vector3d z = axis_frame.R.col(2);
      at = axis_frame.p + z * z.dot(origin - axis_frame.p);
    }
    scene.markers.push_back({at, i});
    scene.label_of_joint.push_back(
        fmt::format("{} {}  {} N\u00b7m", i + 1, d.joints[std::size_t(i)].name, torque_text(tau[i])));
    y_sum += origin.y();
  }
  scene.centre_y = y_sum / double(n + 1);
  return scene;
}

}  // namespace

std::string body_svg(const AnyModel<double>& model, const BodyDrawing& drawing) {
  Data<AnyModel<double>> data(model);
  forward_kinematics(model, data, drawing.q);
  const Scene scene = build_scene(model, data, drawing.tau);

  const double header = 30 + 15 * double(drawing.notes.size());
  const ViewRenderer front(scene, front_view, 0, header);
  const ViewRenderer side(scene, side_view, front.width(), header);
  // wide enough for the title and the notes too
  double width = front.width() + side.width();
  width = std::max(width, 24 + 9.1 * double(drawing.title.size()));
  for (const auto& note : drawing.notes) width = std::max(width, 24 + char_width * double(note.size()));
  const double height = header + std::max(front.height(), side.height());

  std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  const auto out = std::back_inserter(svg);
  fmt::format_to(
      out,
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.0f}\" height=\"{1:.0f}\" viewBox=\"0 0 {0:.0f} {1:.0f}\" "
      "font-family=\"DejaVu Sans Mono, Menlo, Consolas, monospace\">\n",
      width, height);
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  fmt::format_to(out, "<text x=\"12\" y=\"22\" font-size=\"15\" font-weight=\"bold\">{}</text>\n",
                 escape(drawing.title));
  for (std::size_t k = 0; k < drawing.notes.size(); ++k)
    fmt::format_to(out, "<text x=\"12\" y=\"{:.0f}\" font-size=\"11\" fill=\"#4a5568\">{}</text>\n",
                   40 + 15 * double(k), escape(drawing.notes[k]));
  front.draw(svg);
  fmt::format_to(out, "<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\" stroke=\"#e2e8f0\"/>\n",
                 front.width(), header, height - 10);
  side.draw(svg);
  svg += "</svg>\n";
  return svg;
}

}  // namespace humandyn::cli
