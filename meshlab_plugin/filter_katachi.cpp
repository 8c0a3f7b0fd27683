// katachi MeshLab plugin: the plugin class (see filter_katachi.h). Nothing here but
// forwarding to filters.h and MeshLab's two ways of reporting.
//
// License: MIT OR Apache-2.0.

#include "filter_katachi.h"
#include "filters.h"

#include <climits>

KatachiFilterPlugin::KatachiFilterPlugin() {
    for (int id : katachi_meshlab::filter_ids()) {
        typeList.push_back(id);
        actionList.push_back(new QAction(katachi_meshlab::filter_name(id), this));
    }
}

QString KatachiFilterPlugin::pluginName() const { return "FilterKatachi"; }

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API

QString KatachiFilterPlugin::filterName(ActionIDType filter) const {
    return katachi_meshlab::filter_name(filter);
}
QString KatachiFilterPlugin::filterInfo(ActionIDType filter) const {
    return katachi_meshlab::filter_info(filter);
}
FilterPlugin::FilterClass KatachiFilterPlugin::getClass(const QAction *) const {
    return FilterPlugin::Remeshing;
}
int KatachiFilterPlugin::getPreConditions(const QAction *) const {
    return MeshModel::MM_FACENUMBER;
}
int KatachiFilterPlugin::postCondition(const QAction *a) const {
    return katachi_meshlab::post_condition(ID(a));
}
RichParameterList KatachiFilterPlugin::initParameterList(const QAction *a, const MeshDocument &) {
    RichParameterList par;
    katachi_meshlab::add_parameters(ID(a), par);
    return par;
}
std::map<std::string, QVariant> KatachiFilterPlugin::applyFilter(
    const QAction *action, const RichParameterList &params, MeshDocument &md,
    unsigned int & /*postConditionMask*/, vcg::CallBackPos *cb) {
    QString error;
    katachi_meshlab::Outputs outputs;
    const auto note = [this](const QString &m) { log("%s", qUtf8Printable(m)); };
    // MeshLab and pymeshlab show an MLException's text as the filter's error.
    if (!katachi_meshlab::run(ID(action), md, params, cb, note, outputs, error))
        throw MLException(error);
    // pymeshlab hands these to Python: int, float and numpy arrays (Eigen::VectorXd).
    std::map<std::string, QVariant> values;
    for (const auto &c : outputs.counts) // pymeshlab converts int, not qlonglong
        values[c.first] = c.second <= INT_MAX ? QVariant(int(c.second))
                                              : QVariant(double(c.second));
    for (const auto &n : outputs.numbers) values[n.first] = QVariant(n.second);
    for (const auto &v : outputs.vectors) {
        Eigen::VectorXd x(Eigen::Index(v.second.size()));
        for (size_t i = 0; i < v.second.size(); ++i) x[Eigen::Index(i)] = v.second[i];
        values[v.first] = QVariant::fromValue(x);
    }
    return values;
}

#else // MeshLab 2020.09

QString KatachiFilterPlugin::filterName(FilterIDType filter) const {
    return katachi_meshlab::filter_name(filter);
}
QString KatachiFilterPlugin::filterInfo(FilterIDType filter) const {
    return katachi_meshlab::filter_info(filter);
}
MeshFilterInterface::FilterClass KatachiFilterPlugin::getClass(QAction *) {
    return MeshFilterInterface::Remeshing;
}
int KatachiFilterPlugin::getPreConditions(QAction *) const { return MeshModel::MM_FACENUMBER; }
int KatachiFilterPlugin::postCondition(QAction *a) const {
    return katachi_meshlab::post_condition(ID(a));
}
void KatachiFilterPlugin::initParameterSet(QAction *a, MeshDocument &, RichParameterList &par) {
    katachi_meshlab::add_parameters(ID(a), par);
}
bool KatachiFilterPlugin::applyFilter(QAction *filter, MeshDocument &md,
                                      const RichParameterList &par, vcg::CallBackPos *cb) {
    errorMessage.clear();
    QString error;
    katachi_meshlab::Outputs outputs; // MeshLab 2020.09 has no channel for them
    const auto note = [this](const QString &m) {
        Log(GLLogStream::FILTER, "%s", qUtf8Printable(m));
    };
    if (katachi_meshlab::run(ID(filter), md, par, cb, note, outputs, error)) return true;
    errorMessage = error;
    // meshlabserver prints the filter's log but not errorMessage: log it too.
    Log(GLLogStream::SYSTEM, "%s", qUtf8Printable(error));
    return false;
}

MESHLAB_PLUGIN_NAME_EXPORTER(KatachiFilterPlugin)

#endif
