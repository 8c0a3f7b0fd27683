// katachi MeshLab plugin: the filters, independent of MeshLab's plugin interface.
//
// Everything a filter does (its name, description, parameters, and the run that reads the
// layer, calls katachi and writes the result) is here, once, for every MeshLab version the
// plugin builds for. The plugin class (filter_katachi.h) only forwards MeshLab's calls.
//
// License: MIT OR Apache-2.0.

#ifndef KATACHI_MESHLAB_FILTERS_H
#define KATACHI_MESHLAB_FILTERS_H

#include "meshlab_api.h"

#include <QString>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace katachi_meshlab {

/// The filters' ids (MeshLab's action ids).
enum FilterId { SUBDIVIDE = 0, CUT = 1 };

/// Every filter, in menu order.
const std::vector<int> &filter_ids();

/// The name in MeshLab's menu and scripts ("katachi: Solid-aware subdivision"); pymeshlab
/// derives its function name from it. Empty for an unknown id.
QString filter_name(int filter);

/// The description shown in the filter's dialog (HTML).
QString filter_info(int filter);

/// MeshModel::MM_* mask of what the filter changes.
int post_condition(int filter);

/// Adds the filter's parameters, with their defaults, to `par`.
void add_parameters(int filter, RichParameterList &par);

/// Where a filter's report lines go (MeshLab's log).
using Note = std::function<void(const QString &)>;

/// What a filter reports besides its log: pymeshlab returns it from apply_filter as a dict
/// (MeshLab 2020.09 has no such channel). Keys are snake_case.
struct Outputs {
    std::map<std::string, long long> counts;
    std::map<std::string, double> numbers;
    std::map<std::string, std::vector<double>> vectors;
};

/// Runs `filter` on the current layer of `md`. On failure returns false with `error` set
/// (katachi's message, starting "katachi") and the document unchanged.
bool run(int filter, MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb,
         const Note &note, Outputs &outputs, QString &error);

} // namespace katachi_meshlab

#endif
