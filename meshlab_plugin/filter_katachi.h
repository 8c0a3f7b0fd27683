// katachi MeshLab plugin: the plugin class, the one place where MeshLab's two plugin
// interfaces differ.
//
// MeshLab 2020.09 (Debian 12's; meshlabserver) loads a MeshFilterInterface; MeshLab 2022.02
// and later (2025.07, its AppImage/flatpak, pymeshlab) load a FilterPlugin. Both builds come
// from the same sources: this class forwards each call to filters.h, and only the
// signatures, the error channel (2020.09: return false with errorMessage; 2025.07: throw
// MLException) and the log differ. CMake defines KATACHI_MESHLAB_FILTER_PLUGIN_API for the
// newer interface (meshlab_api.h).
//
// License: MIT OR Apache-2.0.

#ifndef KATACHI_MESHLAB_FILTER_KATACHI_H
#define KATACHI_MESHLAB_FILTER_KATACHI_H

#include "meshlab_api.h"

#include <QObject>

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API

class KatachiFilterPlugin : public QObject, public FilterPlugin
{
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
    Q_INTERFACES(FilterPlugin)

public:
    KatachiFilterPlugin();
    QString pluginName() const override;
    QString vendor() const override { return "katachi"; }
    QString filterName(ActionIDType filter) const override;
    QString filterInfo(ActionIDType filter) const override;
    FilterClass getClass(const QAction *) const override;
    FilterArity filterArity(const QAction *) const override { return SINGLE_MESH; }
    int getPreConditions(const QAction *) const override;
    int postCondition(const QAction *) const override;
    RichParameterList initParameterList(const QAction *, const MeshDocument &md) override;
    std::map<std::string, QVariant> applyFilter(const QAction *action,
                                                const RichParameterList &params,
                                                MeshDocument &md,
                                                unsigned int &postConditionMask,
                                                vcg::CallBackPos *cb) override;
};

#else // MeshLab 2020.09

class KatachiFilterPlugin : public QObject, public MeshFilterInterface
{
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)

public:
    KatachiFilterPlugin();
    QString pluginName() const override;
    QString filterName(FilterIDType filter) const override;
    QString filterInfo(FilterIDType filter) const override;
    FilterClass getClass(QAction *) override;
    FILTER_ARITY filterArity(QAction *) const override { return SINGLE_MESH; }
    int getRequirements(QAction *) override { return MeshModel::MM_NONE; }
    int getPreConditions(QAction *) const override;
    int postCondition(QAction *) const override;
    void initParameterSet(QAction *, MeshDocument &md, RichParameterList &par) override;
    bool applyFilter(QAction *filter, MeshDocument &md, const RichParameterList &par,
                     vcg::CallBackPos *cb) override;
};

#endif

#endif
