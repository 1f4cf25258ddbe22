#include "capture/preview.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "dataset/raster.h"

namespace deixis::capture {

namespace {

using dataset::Canvas;
using dataset::Rgb;

constexpr int kWidth = 1200;
constexpr int kHeight = 920;
constexpr Rgb kBackground{255, 255, 255};
constexpr Rgb kInk{40, 40, 40};
constexpr Rgb kGrid{225, 225, 225};
constexpr std::array<Rgb, 3> kLabelColours = {Rgb{40, 110, 220}, Rgb{220, 60, 50},
                                              Rgb{40, 160, 80}};
constexpr std::array<const char*, 3> kLabelNames = {"gaze", "deictic", "idle"};
constexpr Rgb kTip{220, 60, 50};
constexpr Rgb kHead{40, 110, 220};
constexpr Rgb kTarget{230, 150, 30};
constexpr Rgb kPartner{150, 90, 200};

struct Box {
  int x0, y0, x1, y1;
};

// The progression curves: labels thick, predictions thin.
void draw_curves(Canvas& c, const Sequence& s, const std::vector<Labels>* predictions, Box b) {
  const double duration = s.frames.back().time;
  auto px = [&](double t) { return static_cast<float>(b.x0 + (b.x1 - b.x0) * t / duration); };
  auto py = [&](float v) { return static_cast<float>(b.y1) - v * static_cast<float>(b.y1 - b.y0); };
  for (const float v : {0.0f, 0.5f, 1.0f}) {
    c.line(static_cast<float>(b.x0), py(v), static_cast<float>(b.x1), py(v), kGrid);
    char tick[8];
    std::snprintf(tick, sizeof tick, "%.1f", static_cast<double>(v));
    c.text(static_cast<float>(b.x0 - 28), py(v) - 4, tick, kInk);
  }
  for (int second = 0; second <= static_cast<int>(duration); ++second) {
    c.line(px(second), static_cast<float>(b.y0), px(second), static_cast<float>(b.y1), kGrid);
    c.text(px(second) - 3, static_cast<float>(b.y1 + 6), std::to_string(second), kInk);
  }
  c.text(static_cast<float>(b.x1 - 40), static_cast<float>(b.y1 + 6), "time (s)", kInk);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.phase_keys[i]) {
      c.line(px(s.frames[i].time), static_cast<float>(b.y1 - 6), px(s.frames[i].time),
             static_cast<float>(b.y1), kInk);
    }
  }
  for (int k = 0; k < 3; ++k) {
    for (std::size_t i = 1; i < s.size(); ++i) {
      c.line(px(s.frames[i - 1].time), py(s.labels[i - 1][k]), px(s.frames[i].time),
             py(s.labels[i][k]), kLabelColours[k], 3.0f, 0.8f);
      if (predictions) {
        c.line(px(s.frames[i - 1].time), py((*predictions)[i - 1][k]), px(s.frames[i].time),
               py((*predictions)[i][k]), kLabelColours[k], 1.0f);
      }
    }
    const float lx = static_cast<float>(b.x0 + 10 + 90 * k);
    c.line(lx, static_cast<float>(b.y0 - 10), lx + 20, static_cast<float>(b.y0 - 10),
           kLabelColours[k], 3.0f);
    c.text(lx + 25, static_cast<float>(b.y0 - 14), kLabelNames[k], kInk);
  }
  if (predictions) {
    c.text(static_cast<float>(b.x0 + 290), static_cast<float>(b.y0 - 14),
           "thick: labels   thin: the authors' MPNet", kInk);
  }
}

// A view of the person's root frame (x right, y up, −z forward): `project` maps a root-frame point
// to (horizontal, vertical) metres of the view.
struct View {
  Box box;
  float scale = 1;
  float cx = 0, cy = 0;  // view metres at the box centre
  Vec3 (*project)(const Vec3&) = nullptr;

  std::pair<float, float> pixel(const Vec3& p) const {
    const Vec3 q = project(p);
    return {0.5f * static_cast<float>(box.x0 + box.x1) + (q.x() - cx) * scale,
            0.5f * static_cast<float>(box.y0 + box.y1) - (q.y() - cy) * scale};
  }
};

Vec3 from_above(const Vec3& p) {
  return {p.x(), -p.z(), 0};  // right, forward
}
Vec3 from_side(const Vec3& p) {
  return {-p.z(), p.y(), 0};  // forward, up
}

View fit(Box box, Vec3 (*project)(const Vec3&), const std::vector<Vec3>& points) {
  View v{box, 1, 0, 0, project};
  Eigen::Vector2f lo(1e9f, 1e9f);
  Eigen::Vector2f hi(-1e9f, -1e9f);
  for (const Vec3& p : points) {
    const Vec3 q = project(p);
    lo = lo.cwiseMin(q.head<2>());
    hi = hi.cwiseMax(q.head<2>());
  }
  const Eigen::Vector2f size = (hi - lo).cwiseMax(Eigen::Vector2f(1.0f, 1.0f)) * 1.15f;
  v.scale = std::min(static_cast<float>(box.x1 - box.x0) / size.x(),
                     static_cast<float>(box.y1 - box.y0) / size.y());
  v.cx = 0.5f * (lo.x() + hi.x());
  v.cy = 0.5f * (lo.y() + hi.y());
  return v;
}

void segment(Canvas& c, const View& v, const Vec3& a, const Vec3& b, Rgb colour, float width,
             float alpha = 1.0f) {
  const auto [x0, y0] = v.pixel(a);
  const auto [x1, y1] = v.pixel(b);
  c.line(x0, y0, x1, y1, colour, width, alpha);
}

void stick_figure(Canvas& c, const View& v, const Joints& j, float floor, float alpha) {
  const Rgb body{90, 90, 90};
  segment(c, v, j.hip, Vec3(j.hip.x(), floor, j.hip.z()), body, 3, alpha);  // legs, standing
  segment(c, v, j.hip, j.neck, body, 3, alpha);
  segment(c, v, j.neck, j.head, body, 3, alpha);
  segment(c, v, j.shoulder[0], j.shoulder[1], body, 3, alpha);
  for (int h = 0; h < 2; ++h) {
    segment(c, v, j.shoulder[h], j.elbow[h], body, 2, alpha);
    segment(c, v, j.elbow[h], j.wrist[h], body, 2, alpha);
    segment(c, v, j.wrist[h], j.tip[h], body, 1.5f, alpha);
  }
  const auto [hx, hy] = v.pixel(j.head);
  c.disc(hx, hy, 4, body, alpha);
}

void draw_view(Canvas& c, const Sequence& s, const View& v, const Pose& T_root_world,
               const char* title) {
  c.clip(v.box.x0, v.box.y0, v.box.x1, v.box.y1);
  c.rect(v.box.x0, v.box.y0, v.box.x1, v.box.y1, Rgb{250, 250, 250});
  c.text(static_cast<float>(v.box.x0 + 6), static_cast<float>(v.box.y0 + 6), title, kInk, 1.5f);
  auto local = [&](const Vec3& p) { return transform_point(T_root_world, p); };
  // A 1 m grid.
  const float ox = 0.5f * static_cast<float>(v.box.x0 + v.box.x1);
  const float oy = 0.5f * static_cast<float>(v.box.y0 + v.box.y1);
  const float half_w = 0.5f * static_cast<float>(v.box.x1 - v.box.x0) / v.scale;
  const float half_h = 0.5f * static_cast<float>(v.box.y1 - v.box.y0) / v.scale;
  for (int m = static_cast<int>(std::ceil(v.cx - half_w)); m <= static_cast<int>(v.cx + half_w);
       ++m) {
    const float x = ox + (static_cast<float>(m) - v.cx) * v.scale;
    c.line(x, static_cast<float>(v.box.y0), x, static_cast<float>(v.box.y1), kGrid);
  }
  for (int m = static_cast<int>(std::ceil(v.cy - half_h)); m <= static_cast<int>(v.cy + half_h);
       ++m) {
    const float y = oy - (static_cast<float>(m) - v.cy) * v.scale;
    c.line(static_cast<float>(v.box.x0), y, static_cast<float>(v.box.x1), y, kGrid);
  }
  // Targets.
  for (const TargetObject& t : s.targets) {
    const auto [x, y] = v.pixel(local(t.position));
    const float r = std::max(4.0f, 0.5f * t.size.x() * v.scale);
    const Rgb colour = t.id == kPartnerTarget ? kPartner : kTarget;
    c.disc(x, y, r, colour, 0.5f);
    c.circle(x, y, r, colour, 1.5f);
    c.text(x + r + 3, y - 4, t.id == kPartnerTarget ? "partner" : std::to_string(t.id), kInk);
  }
  const int hand = index(s.calibration.deictic_hand);
  // Stick figures once a second, faint; at completion states (deictic = 1 reached), bold.
  for (std::size_t i = 0; i < s.size(); i += 30) {
    Joints j = s.joints[i];
    for (Vec3* p : {&j.hip, &j.neck, &j.head, &j.eye[0], &j.eye[1], &j.shoulder[0], &j.shoulder[1],
                    &j.elbow[0], &j.elbow[1], &j.wrist[0], &j.wrist[1], &j.tip[0], &j.tip[1]}) {
      *p = local(*p);
    }
    const bool complete = s.labels[i][1] >= 1.0f;
    const float floor = -s.calibration.T_world_root.translation.y();
    stick_figure(c, v, j, floor, complete ? 0.9f : 0.25f);
  }
  // Paths of the deictic fingertip and of H, and gaze rays every 0.5 s.
  for (std::size_t i = 1; i < s.size(); ++i) {
    segment(c, v, local(s.joints[i - 1].tip[hand]), local(s.joints[i].tip[hand]), kTip, 1.5f);
    segment(c, v, local(s.joints[i - 1].head), local(s.joints[i].head), kHead, 1.5f);
  }
  for (std::size_t i = 0; i < s.size(); i += 15) {
    const Vec3 h = local(s.frames[i].T_world_head.translation);
    const Vec3 g = T_root_world.rotation * s.frames[i].gaze;
    segment(c, v, h, h + 0.6f * g, kHead, 1.0f, 0.6f);
  }
  c.reset_clip();
}

}  // namespace

void write_preview(const Sequence& s, const std::vector<Labels>* predictions,
                   const std::string& title, const std::filesystem::path& path) {
  if (s.joints.size() != s.size() || s.size() < 2) {
    throw Error("preview: the sequence has no skeleton (preview a freshly performed sequence)");
  }
  if (predictions && predictions->size() != s.size()) {
    throw Error("preview: predictions and frames differ in count");
  }
  Canvas c(kWidth, kHeight, kBackground);
  c.text(20, 10, title, kInk, 2.0f);
  draw_curves(c, s, predictions, Box{60, 60, 1180, 300});

  const Pose T_root_world = inverse(s.calibration.T_world_root);
  std::vector<Vec3> points;
  for (const TargetObject& t : s.targets) {
    points.push_back(transform_point(T_root_world, t.position));
  }
  for (const Joints& j : s.joints) {
    for (const Vec3& p :
         {j.head, j.shoulder[0], j.shoulder[1], j.elbow[0], j.elbow[1], j.tip[0], j.tip[1]}) {
      points.push_back(transform_point(T_root_world, p));
    }
    points.push_back(transform_point(T_root_world, j.hip) - Vec3(0, 0.9f, 0));  // feet
  }
  const View above = fit(Box{20, 340, 590, 910}, from_above, points);
  const View side = fit(Box{610, 340, 1180, 910}, from_side, points);
  draw_view(c, s, above, T_root_world, "from above (forward is up)");
  draw_view(c, s, side, T_root_world, "from the side (forward is right)");
  c.write_png(path);
}

}  // namespace deixis::capture
