// Plotting results with gnuplot: a data file and a script beside the
// picture; the terminal follows the extension (.svg: svg, .png: pngcairo
// when gnuplot has it, else png).
#pragma once

#include "ldae/Simulation.h"

#include <string>
#include <vector>

namespace ldae::runtime {

/// Plots `columns` (all but time when empty) of `result` against time into
/// `path` (.svg or .png). Writes `path`.dat and `path`.gp beside it.
/// Returns an Error when gnuplot is missing, fails, or a name is unknown.
Expected<bool> plot(const SimResult &result, const std::string &path,
                    const std::vector<std::string> &columns = {});

} // namespace ldae::runtime
