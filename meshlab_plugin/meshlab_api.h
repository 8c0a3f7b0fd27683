// katachi MeshLab plugin: which of MeshLab's plugin interfaces the build uses.
//
// MeshLab 2020.09 (Debian 12's) has MeshFilterInterface in <common/interfaces.h>; MeshLab
// 2022.02 and later (2025.07, pymeshlab) have FilterPlugin in
// <common/plugins/interfaces/filter_plugin.h>. CMake sets KATACHI_MESHLAB_FILTER_PLUGIN_API
// from the source tree it is given (moc must see it too, so it is not guessed here). The
// names that differ between the two and that the filters use are aliased here; the plugin
// class (filter_katachi.h) holds the rest of the difference.
//
// License: MIT OR Apache-2.0.

#ifndef KATACHI_MESHLAB_MESHLAB_API_H
#define KATACHI_MESHLAB_MESHLAB_API_H

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API
#include <common/plugins/interfaces/filter_plugin.h>
#else
#include <common/interfaces.h>
#endif

namespace katachi_meshlab {

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API
using RichShotParameter = RichShot;
inline void update_box_and_normals(MeshModel &m) { m.updateBoxAndNormals(); }
#else
using RichShotParameter = RichShotf;
inline void update_box_and_normals(MeshModel &m) { m.UpdateBoxAndNormals(); }
#endif

} // namespace katachi_meshlab

#endif
