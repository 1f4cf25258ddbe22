#include "sim/sim_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include "sim/sim_panel_parts.h"

namespace deixis::sim {

namespace {

using panel::button;
using panel::note;

constexpr float kPlotHeight = 34.0f;
constexpr float kPlotLabelWidth = 90.0f;  // px beside each plot for its name

void plot(const char* label, const Ring& ring, float lo, float hi, const char* unit,
          PanelWidgets* widgets) {
  char overlay[32];
  std::snprintf(overlay, sizeof overlay, "%.2f%s", static_cast<double>(ring.last()), unit);
  // An explicit width: a negative one (right-aligned) collapses inside a table column in 1.86.
  const float width = std::max(ImGui::GetContentRegionAvail().x - kPlotLabelWidth, 40.0f);
  ImGui::PlotLines(label, ring.data(), ring.count(), ring.offset(), overlay, lo, hi,
                   ImVec2(width, kPlotHeight));
  note(widgets, label);
}

void progressions(const SimHistory& h, PanelWidgets* widgets) {
  ImGui::TextUnformatted("Remote avatar: MPNet progressions, blend weights");
  plot("gaze", h.progression[0], 0.0f, 1.0f, "", widgets);
  plot("deictic", h.progression[1], 0.0f, 1.0f, "", widgets);
  plot("idle", h.progression[2], 0.0f, 1.0f, "", widgets);
  plot("head weight", h.head_weight, 0.0f, 1.0f, "", widgets);
  plot("hand weight", h.hand_weight, 0.0f, 1.0f, "", widgets);
}

const char* object_name(std::span<const TargetObject> objects, TargetId id) {
  for (const TargetObject& o : objects) {
    if (o.id == id) {
      return o.name.c_str();
    }
  }
  return "(none)";
}

void user_controls(const PanelStatus& s, PanelEdits& edits, PanelActions& a,
                   PanelWidgets* widgets) {
  ImGui::TextUnformatted(s.scripted_user ? "Virtual user: scripted (--script)"
                                         : "Virtual user: mouse and keys");
  ImGui::BeginDisabled(s.scripted_user);
  a.look_at_partner = button("Look at partner (P)", widgets);
  ImGui::SameLine();
  a.explain = button("Explain (E)", widgets);
  ImGui::SameLine();
  a.rest = button("Rest (R)", widgets);
  ImGui::SetNextItemWidth(140.0f);
  if (ImGui::BeginCombo("##object", object_name(s.local_objects, edits.selected))) {
    for (const TargetObject& o : s.local_objects) {
      if (ImGui::Selectable(o.name.c_str(), o.id == edits.selected)) {
        edits.selected = o.id;
      }
    }
    ImGui::EndCombo();
  }
  note(widgets, "object");
  ImGui::SameLine();
  if (button("Point", widgets)) {
    a.point = edits.selected;
  }
  ImGui::SameLine();
  if (button("Touch", widgets)) {
    a.touch = edits.selected;
  }
  ImGui::EndDisabled();
  a.reset_objects = button("Put B's objects back", widgets);
  ImGui::TextWrapped("%.*s", static_cast<int>(s.status.size()), s.status.data());
  note(widgets, "status");
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
  ImGui::TextWrapped(
      "Left view: right-drag looks, click points, shift-click or middle-click touches. Right "
      "view: drag an object across the room.");
  ImGui::PopStyleColor();
}

void timings(const SimHistory& h, PanelWidgets* widgets) {
  ImGui::Text("translation + IK  p50 %.3f  p99 %.3f ms",
              static_cast<double>(h.tick_ms.quantile(0.5f)),
              static_cast<double>(h.tick_ms.quantile(0.99f)));
  note(widgets, "translation timing");
  ImGui::Text("render (2 views)  p50 %.2f  p99 %.2f ms",
              static_cast<double>(h.render_ms.quantile(0.5f)),
              static_cast<double>(h.render_ms.quantile(0.99f)));
  note(widgets, "render timing");
  plot("frame", h.frame_ms, 0.0f, 50.0f, " ms", widgets);
}

void avatar_choice(const PanelStatus& s, PanelEdits& edits, PanelActions& a,
                   PanelWidgets* widgets) {
  ImGui::Text("Avatar in B: %.*s", static_cast<int>(s.avatar.size()), s.avatar.data());
  note(widgets, "avatar");
  ImGui::SetNextItemWidth(-110.0f);
  ImGui::InputTextWithHint("##glb", "a .glb (empty: the default avatar)", edits.avatar_path.data(),
                           edits.avatar_path.size());
  note(widgets, "avatar path");
  ImGui::SameLine();
  a.load_avatar = button("Load avatar", widgets);
  if (!s.avatar_note.empty()) {
    ImGui::TextWrapped("%.*s", static_cast<int>(s.avatar_note.size()), s.avatar_note.data());
  }
}

}  // namespace

void panel::note(PanelWidgets* widgets, std::string_view label) {
  if (widgets == nullptr || widgets->count == widgets->items.size()) {
    return;
  }
  const ImVec2 lo = ImGui::GetItemRectMin();
  const ImVec2 hi = ImGui::GetItemRectMax();
  widgets->items[widgets->count++] = {label, lo.x, lo.y, hi.x, hi.y};
}

bool panel::button(const char* label, PanelWidgets* widgets) {
  const bool clicked = ImGui::Button(label);
  note(widgets, label);
  return clicked;
}

const PanelWidgets::Item* PanelWidgets::find(std::string_view label) const {
  for (std::size_t i = 0; i < count; ++i) {
    if (items[i].label == label) {
      return &items[i];
    }
  }
  return nullptr;
}

PanelActions draw_panel(const ViewRect& rect, const PanelStatus& s, PanelEdits& edits,
                        PanelWidgets* widgets) {
  if (widgets != nullptr) {
    widgets->count = 0;
  }
  PanelActions a;
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(rect.x), static_cast<float>(rect.y)));
  ImGui::SetNextWindowSize(ImVec2(static_cast<float>(rect.width), static_cast<float>(rect.height)));
  constexpr ImGuiWindowFlags kFlags = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                      ImGuiWindowFlags_NoCollapse |
                                      ImGuiWindowFlags_NoSavedSettings;
  char title[96];
  std::snprintf(title, sizeof title, "Deixis sim  %.1f s, %llu ticks, avatar %s###panel", s.seconds,
                static_cast<unsigned long long>(s.ticks), s.avatar_visible ? "shown" : "hidden");
  if (ImGui::Begin(title, nullptr, kFlags) && s.history != nullptr &&
      ImGui::BeginTable("columns", 3, ImGuiTableFlags_BordersInnerV)) {
    ImGui::TableNextColumn();
    progressions(*s.history, widgets);
    ImGui::TableNextColumn();
    user_controls(s, edits, a, widgets);
    avatar_choice(s, edits, a, widgets);
    ImGui::TableNextColumn();
    // The network first: its form must stay in view when the window is small.
    panel::network_section(s, edits.network, a, widgets);
    ImGui::Separator();
    timings(*s.history, widgets);
    ImGui::EndTable();
  }
  ImGui::End();
  return a;
}

}  // namespace deixis::sim
