#pragma once
// The simulator panel's pieces shared by its files (sim_panel.cpp lays the panel out,
// sim_panel_network.cpp draws its network section); not for other callers.

#include <string_view>

#include "sim/sim_panel.h"

namespace deixis::sim::panel {

// Remembers where the last widget was drawn under `label`.
void note(PanelWidgets* widgets, std::string_view label);
// A button, noted under its label; true when clicked.
bool button(const char* label, PanelWidgets* widgets);

// While a session runs, its state and a Leave button; otherwise the form that starts one (Start,
// off in a fixed-step run, saying why) and how the last session ended, a failure in red.
void network_section(const PanelStatus& s, NetworkForm& form, PanelActions& a,
                     PanelWidgets* widgets);

}  // namespace deixis::sim::panel
