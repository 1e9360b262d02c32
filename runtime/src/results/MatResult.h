// A result in the .mat layout of OpenModelica and Dymola (docs/results.md,
// "The .mat file"), so their readers (OMPython, DyMat, scipy.io.loadmat,
// MATLAB) read ours.
#pragma once

#include "ldae/ResultWriter.h"
#include "ldae/Simulation.h"

#include <memory>
#include <string>

namespace ldae::runtime {

/// The result file `path` as a MATLAB v4 file written as the run goes:
/// Aclass, name, description, dataInfo, data_1 (every parameter of the
/// run), data_2 (the trajectories, time first, one column per time point;
/// an alias column is stored once and referred to with sign), in the
/// "binTrans" layout OpenModelica's readers read.
std::unique_ptr<ResultFile> matResultFile(const std::string &path);

} // namespace ldae::runtime
