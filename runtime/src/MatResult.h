// A result in the .mat layout of OpenModelica and Dymola (docs/results.md,
// "The .mat file"), so their readers (OMPython, DyMat, scipy.io.loadmat,
// MATLAB) read ours.
#pragma once

#include "ldae/Simulation.h"

#include <string>

namespace ldae::runtime {

/// Writes `result` to `path` as a MATLAB v4 file: Aclass, name,
/// description, dataInfo, data_1 (every parameter of the run), data_2 (the
/// trajectories, time first; an alias column is stored once and referred
/// to with sign), all transposed ("binTrans").
Expected<bool> writeMat(const SimResult &result, const std::string &path);

} // namespace ldae::runtime
