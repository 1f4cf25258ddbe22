#include <imgui.h>

#include <algorithm>
#include <array>

#include "sim/sim_panel_parts.h"

namespace deixis::sim::panel {

namespace {

const ImVec4 kFailure(1.0f, 0.35f, 0.3f, 1.0f);
constexpr float kPortWidth = 70.0f;  // px: five digits

// A line of text, in red when `failed`.
void line(std::string_view text, bool failed, PanelWidgets* widgets, std::string_view label) {
  if (failed) {
    ImGui::PushStyleColor(ImGuiCol_Text, kFailure);
  }
  ImGui::TextWrapped("%.*s", static_cast<int>(text.size()), text.data());
  note(widgets, label);
  if (failed) {
    ImGui::PopStyleColor();
  }
}

// Each remote person's link as the headset's panel says it (site/link_health.h): live or not,
// round trip, jitter-buffer delay, frames dropped in the last seconds.
void people_links(const PanelNetwork& n, PanelWidgets* widgets) {
  std::array<char, 160> text{};
  for (const site::LivePerson& p : n.people) {
    site::format_link_line(p.site, p.link, text);
    ImGui::BulletText("%s", text.data());
    note(widgets, "person link");
  }
}

// A room's members: each one's site and whether their avatar is shown now.
void room_people(const PanelNetwork& n, PanelWidgets* widgets) {
  ImGui::TextWrapped("Room %.*s: tracking sent %llu, %zu here", static_cast<int>(n.room.size()),
                     n.room.data(), static_cast<unsigned long long>(n.sent), n.people.size());
  note(widgets, "network counts");
  people_links(n, widgets);
}

// Role, address, who came and what flows, the state; Leave ends it (the form comes back).
void session_state(const PanelNetwork& n, PanelActions& a, PanelWidgets* widgets) {
  ImGui::TextWrapped("Network: %.*s %.*s:%u, passphrase %s", static_cast<int>(n.role.size()),
                     n.role.data(), static_cast<int>(n.address.size()), n.address.data(), n.port,
                     n.passphrase ? "set" : "none");
  note(widgets, "network");
  if (!n.room.empty()) {
    room_people(n, widgets);
  } else {
    ImGui::TextWrapped("site %.*s: tracking sent %llu, frames played %llu",
                       static_cast<int>(n.peer_site.size()), n.peer_site.data(),
                       static_cast<unsigned long long>(n.sent),
                       static_cast<unsigned long long>(n.played));
    note(widgets, "network counts");
    people_links(n, widgets);
  }
  a.leave_network = button("Leave", widgets);
  ImGui::SameLine();
  line(n.state, n.failed, widgets, "network state");
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
  ImGui::TextWrapped(
      n.room.empty() ? "Left: their person in room A. Right: room B translated here (a preview)."
                     : "Left: everyone in the room on A's spots. Right: room B translated here "
                       "(a preview).");
  ImGui::PopStyleColor();
}

// Join: the host's HOST:PORT; host: the port to listen on. A click selects the whole field, so
// typing replaces what is there. Each field's words stand beside it as text, not as its label,
// so that the rectangle noted (and a scripted click at its centre) is the field's own.
void address_field(NetworkForm& form, PanelWidgets* widgets) {
  constexpr ImGuiInputTextFlags kFlags = ImGuiInputTextFlags_AutoSelectAll;
  if (form.host) {
    ImGui::SetNextItemWidth(kPortWidth);
    ImGui::InputText("##port", form.port.data(), form.port.size(),
                     kFlags | ImGuiInputTextFlags_CharsDecimal);
    note(widgets, "host port");
    ImGui::SameLine();
    ImGui::TextUnformatted("port to listen on (0: any free one)");
    return;
  }
  constexpr const char* kWords = "the host";
  const ImGuiStyle& style = ImGui::GetStyle();
  // An explicit width: a negative one collapses inside a table column in 1.86.
  ImGui::SetNextItemWidth(std::max(
      ImGui::GetContentRegionAvail().x - ImGui::CalcTextSize(kWords).x - style.ItemSpacing.x,
      60.0f));
  ImGui::InputTextWithHint("##endpoint", "address:port", form.endpoint.data(), form.endpoint.size(),
                           kFlags);
  note(widgets, "join address");
  ImGui::SameLine();
  ImGui::TextUnformatted(kWords);
  // A room's name makes the address a relay's (`--connect HOST:PORT --room NAME`).
  ImGui::SetNextItemWidth(std::max(ImGui::GetContentRegionAvail().x, 60.0f));
  ImGui::InputTextWithHint("##room", "room on a relay (empty: the host directly)", form.room.data(),
                           form.room.size(), kFlags);
  note(widgets, "room");
}

// The passphrase, never shown in clear, and Start beside it.
void passphrase_and_start(const PanelStatus& s, NetworkForm& form, PanelActions& a,
                          PanelWidgets* widgets) {
  const ImGuiStyle& style = ImGui::GetStyle();
  const float start_width = ImGui::CalcTextSize("Start").x + 2.0f * style.FramePadding.x;
  ImGui::SetNextItemWidth(
      std::max(ImGui::GetContentRegionAvail().x - start_width - style.ItemSpacing.x, 60.0f));
  ImGui::InputTextWithHint("##passphrase", "passphrase (both sites)", form.passphrase.data(),
                           form.passphrase.size(),
                           ImGuiInputTextFlags_Password | ImGuiInputTextFlags_AutoSelectAll);
  note(widgets, "passphrase");
  ImGui::SameLine();
  const bool off = !s.start_disabled.empty();
  ImGui::BeginDisabled(off);
  a.start_network = button("Start", widgets);
  ImGui::EndDisabled();
  if (off && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
    ImGui::SetTooltip("%.*s", static_cast<int>(s.start_disabled.size()), s.start_disabled.data());
  }
}

void session_form(const PanelStatus& s, NetworkForm& form, PanelActions& a, PanelWidgets* widgets) {
  ImGui::TextUnformatted("Network:");
  note(widgets, "network");
  ImGui::SameLine();
  if (ImGui::RadioButton("Join", !form.host)) {
    form.host = false;
  }
  note(widgets, "Join");
  ImGui::SameLine();
  if (ImGui::RadioButton("Host", form.host)) {
    form.host = true;
  }
  note(widgets, "Host");
  address_field(form, widgets);
  passphrase_and_start(s, form, a, widgets);
  if (!s.form_problem.empty()) {
    line(s.form_problem, true, widgets, "network problem");
  }
}

}  // namespace

void network_section(const PanelStatus& s, NetworkForm& form, PanelActions& a,
                     PanelWidgets* widgets) {
  const PanelNetwork* n = s.network;
  if (n != nullptr && n->running) {
    session_state(*n, a, widgets);
    return;
  }
  session_form(s, form, a, widgets);
  if (n != nullptr) {
    line(n->state, n->failed, widgets, "network state");  // how the last session ended
  }
}

}  // namespace deixis::sim::panel
