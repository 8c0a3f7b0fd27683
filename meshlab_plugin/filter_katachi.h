// katachi MeshLab plugin: the filters "katachi: Solid-aware subdivision" and
// "katachi: Cut by polyline".
//
// Built against MeshLab 2020.09 (MeshFilterInterface), the version Debian 12 ships and the
// one the tests run. MeshLab 2022.02 and later replaced that interface with FilterPlugin;
// the same source compiles against it when <common/plugins/interfaces/filter_plugin.h> is
// found (or KATACHI_MESHLAB_FILTER_PLUGIN_API is defined), but that variant is untested.
//
// License: MIT OR Apache-2.0.

#ifndef KATACHI_MESHLAB_FILTER_KATACHI_H
#define KATACHI_MESHLAB_FILTER_KATACHI_H

#if !defined(KATACHI_MESHLAB_FILTER_PLUGIN_API) && defined(__has_include)
#if __has_include(<common/plugins/interfaces/filter_plugin.h>)
#define KATACHI_MESHLAB_FILTER_PLUGIN_API 1
#endif
#endif

#include <QObject>

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API
#include <common/plugins/interfaces/filter_plugin.h>
#else
#include <common/interfaces.h>
#endif

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API
class KatachiFilterPlugin : public QObject, public FilterPlugin
{
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
    Q_INTERFACES(FilterPlugin)
#else
class KatachiFilterPlugin : public QObject, public MeshFilterInterface
{
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)
#endif

public:
    enum { FP_KATACHI_SUBDIVIDE, FP_KATACHI_CUT };

    KatachiFilterPlugin();

    QString pluginName() const;
#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API
    QString filterName(ActionIDType filter) const;
    QString filterInfo(ActionIDType filter) const;
    FilterClass getClass(const QAction *) const;
    FilterArity filterArity(const QAction *) const { return SINGLE_MESH; }
    int getPreConditions(const QAction *) const;
    int postCondition(const QAction *) const;
    RichParameterList initParameterList(const QAction *, const MeshDocument &md);
    std::map<std::string, QVariant> applyFilter(const QAction *action,
                                                const RichParameterList &params,
                                                MeshDocument &md,
                                                unsigned int &postConditionMask,
                                                vcg::CallBackPos *cb);
#else
    QString filterName(FilterIDType filter) const;
    QString filterInfo(FilterIDType filter) const;
    FilterClass getClass(QAction *);
    FILTER_ARITY filterArity(QAction *) const { return SINGLE_MESH; }
    int getRequirements(QAction *) { return MeshModel::MM_NONE; }
    int getPreConditions(QAction *) const;
    int postCondition(QAction *) const;
    void initParameterSet(QAction *, MeshDocument &md, RichParameterList &par);
    bool applyFilter(QAction *filter, MeshDocument &md, const RichParameterList &par,
                     vcg::CallBackPos *cb);
#endif

private:
    void addParameters(int filter, const MeshDocument &md, RichParameterList &par) const;
    /// Runs filter `filter`; on failure returns false with `error` set and the document
    /// unchanged.
    bool run(int filter, MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb,
             QString &error);
    bool subdivide(MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb,
                   QString &error);
    bool cutByPolyline(MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb,
                       QString &error);
    void note(const QString &message);
};

#endif
