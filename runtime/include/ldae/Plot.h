// Plotting results with gnuplot (docs/plots.md): one panel per group of
// curves that share a unit and a scale, stacked over one time axis, with
// axis labels carrying units, a legend and the model's name as title. A
// data file and a script are written beside the picture; the terminal
// follows the extension (.png: pngcairo when gnuplot has it, else png;
// .svg: svg; .pdf: pdfcairo).
#pragma once

#include "ldae/Simulation.h"

#include <iostream>
#include <string>
#include <vector>

namespace ldae::runtime {

/// The most curves drawn in one panel, and the most panels in one picture.
inline constexpr size_t kPlotCurvesPerPanel = 8;
inline constexpr size_t kPlotPanels = 6;
/// Curves whose largest magnitudes differ by more than this factor (two
/// decades) share no panel: the smaller would be a flat line.
inline constexpr double kPlotScaleRatio = 100;

/// One panel: curves of one unit and one scale.
struct PlotPanel {
  std::string unit;  ///< "" when the curves have none
  std::string label; ///< the y axis label, "v [V]"
  std::vector<int> columns; ///< indices into SimResult::columns, model order
};

/// What a plot draws and what it leaves out.
struct PlotPlan {
  std::vector<PlotPanel> panels;
  /// Curves over the caps (kPlotCurvesPerPanel, kPlotPanels), model order.
  std::vector<std::string> leftOut;
  /// Default curves left out because they stay constant (a ground's
  /// potential), model order.
  std::vector<std::string> constant;
};

/// The panels for `columns` of `result` (names). None named: the
/// continuous variables that are `states` (the model's unknowns,
/// unknownNames; all continuous variables when none of them is a column),
/// neither parameters nor derivatives nor aliases of another column nor,
/// unless all are, constant ones; or the discrete ones when there are no
/// continuous ones. An Error for an unknown name or nothing to draw.
Expected<PlotPlan> planPlot(const SimResult &result,
                            const std::vector<std::string> &columns = {},
                            const std::vector<std::string> &states = {});

/// Plots `columns` of `result` (as planPlot) against time into `path`
/// (.png, .svg or .pdf); writes `path`.dat and `path`.gp beside it. What
/// the caps left out, and how to ask for it, goes to `notes`. An Error
/// when the extension is another, gnuplot is missing or fails, or a name
/// is unknown.
Expected<bool> plot(const SimResult &result, const std::string &path,
                    const std::vector<std::string> &columns = {},
                    const std::vector<std::string> &states = {},
                    std::ostream &notes = std::cerr);

/// The names of `model`'s unknowns (the integrator's: the states and the
/// iteration variables of torn blocks), what plots draw by default.
std::vector<std::string> unknownNames(const ldae_model &model);

} // namespace ldae::runtime
