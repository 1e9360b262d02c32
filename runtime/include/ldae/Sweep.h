// Parameter sweeps from the command line (`ldaec model.lsd --sweep
// "R=1:10:100" --jobs 4 -o sweep.mat`): the members of a grid run on
// threads over one compiled model (the Python module sweeps on Dask,
// docs/python.md).
#pragma once

#include "ldae/ResultWriter.h"
#include "ldae/Simulation.h"

#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace ldae::runtime {

/// The most members a sweep may have (the grid's size): every member's
/// result stays in memory until the file is written.
inline constexpr size_t kMaxSweepMembers = 100000;

/// One swept parameter and its values.
struct SweepAxis {
  std::string name;
  std::vector<double> values;
};

/// `name=first:last:count` (count values evenly spaced, both ends
/// included) or `name=v1,v2,...`; an Error saying what is wrong (the
/// caller quotes `spec`).
Expected<SweepAxis> parseSweepAxis(const std::string &spec);

/// An Error when two axes sweep one name (the grid would hold only the
/// last one's values), or when the grid has more than kMaxSweepMembers
/// members.
Expected<bool> checkSweepAxes(const std::vector<SweepAxis> &axes);

/// The members of the full grid of `axes` (every combination), the first
/// axis varying slowest.
std::vector<std::map<std::string, double>>
sweepMembers(const std::vector<SweepAxis> &axes);

/// One member's outcome: its parameters and its result, or why it failed
/// (a bad option; a numerical failure is status 3 in the result).
struct SweepMember {
  std::map<std::string, double> params;
  Expected<SimResult> result = Error{"not run"};
};

/// Runs one simulation per member on `jobs` threads (0: the machine's
/// cores); `simulate` must be callable from several threads at once.
/// Progress ("member k of N") goes to `progress` when not null.
std::vector<SweepMember>
runSweep(const std::function<Expected<SimResult>(const SimOptions &)> &simulate,
         const SimOptions &base,
         const std::vector<std::map<std::string, double>> &members, int jobs,
         std::ostream *progress);

/// Writes every member to `path` (docs/results.md, "Sweeps").
Expected<bool> writeSweep(const std::vector<SweepMember> &members,
                          const std::string &path, ResultFormat format);

} // namespace ldae::runtime
