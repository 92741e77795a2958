// What the panels remember between frames (selections, the file dialog, histograms) and the
// panels themselves, one function each. Main (window) thread; ImGui builds only.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "core/volume/transfer_function.h"
#include "viewer/viewer_state.h"

namespace frameless {

struct PanelState {
  std::string force_open;  // a panel to expand at the next frame (Panels::open)
  int light = 0, material = 0, object = 0, instance = 0, volume = 0;  // selections
  // The file dialog: the folder shown, its entries (folders first), the path being typed.
  std::string folder;
  std::vector<std::pair<std::string, bool>> entries;  // name, is a folder
  char path[512] = "";
  char camera_file[512] = "camera_path.json";
  // The volume panel: each grid's histogram (64 bins, log counts), and the transfer function
  // being edited for the selected volume.
  std::map<const void*, std::vector<float>> histograms;
  const void* volumes_of = nullptr;  // the scene the histograms and points belong to
  std::vector<TransferPoint> points;
  const void* points_of = nullptr;  // the transfer function `points` was copied from
  int dragged_point = -1;           // the point dragged over the histogram (-1: none)
  int reference_spp = 64;
  float update_percent = 1.0f;  // the sliders applied on release (repartitioning restarts threads)
  int threads = 1;
};

// Each panel's contents (inside its collapsing header).
void settings_panel(Viewer& v, PanelState& p);
void camera_panel(Viewer& v, PanelState& p);
void lights_panel(Viewer& v, PanelState& p);
void materials_panel(Viewer& v, PanelState& p);
void objects_panel(Viewer& v, PanelState& p);
void volumes_panel(Viewer& v, PanelState& p);
void plots_panel(Viewer& v, PanelState& p, const ViewScale& scale);
void files_panel(Viewer& v, PanelState& p);

}  // namespace frameless
