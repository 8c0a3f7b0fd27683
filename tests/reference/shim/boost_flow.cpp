// katachi-reference shim: Boost.Graph's boykov_kolmogorov_max_flow, the reference for katachi's
// own Boykov-Kolmogorov max-flow (seed 003 §3's segmentation).
#include "shim_internal.hpp"

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>

#include <chrono>
#include <string>

namespace {

using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
using Graph = boost::adjacency_list<
    boost::vecS, boost::vecS, boost::directedS, boost::no_property,
    boost::property<boost::edge_capacity_t, long,
                    boost::property<boost::edge_residual_capacity_t, long,
                                    boost::property<boost::edge_reverse_t, Traits::edge_descriptor>>>>;

// An arc a -> b with capacity c and its reverse b -> a with capacity r.
void add_pair(Graph &g, long a, long b, long c, long r) {
    auto cap = boost::get(boost::edge_capacity, g);
    auto rev = boost::get(boost::edge_reverse, g);
    auto e = boost::add_edge(a, b, g).first;
    auto f = boost::add_edge(b, a, g).first;
    cap[e] = c;
    cap[f] = r;
    rev[e] = f;
    rev[f] = e;
}

}  // namespace

extern "C" uint32_t kr_boost_bk_max_flow(const kr_flow_network *net, uint32_t repeats,
                                         kr_result **out) {
    return kr::guarded(out, [&](kr_result &r) {
        if (net == nullptr) {
            throw kr::BadArgument("network is null");
        }
        if (repeats == 0) {
            throw kr::BadArgument("repeats is 0");
        }
        const uint32_t n = net->num_nodes;
        if (n > 0 && (net->source_caps == nullptr || net->sink_caps == nullptr)) {
            throw kr::BadArgument("terminal capacities are null");
        }
        if (net->num_edges > 0 && (net->edge_nodes == nullptr || net->edge_caps == nullptr)) {
            throw kr::BadArgument("edge arrays are null");
        }
        Graph g(n + 2);
        const long source = n, sink = n + 1;
        for (uint32_t i = 0; i < n; ++i) {
            if (net->source_caps[i] < 0 || net->sink_caps[i] < 0) {
                throw kr::BadArgument("node " + std::to_string(i) + " has a negative capacity");
            }
            if (net->source_caps[i] > 0) {
                add_pair(g, source, i, net->source_caps[i], 0);
            }
            if (net->sink_caps[i] > 0) {
                add_pair(g, i, sink, net->sink_caps[i], 0);
            }
        }
        for (uint32_t e = 0; e < net->num_edges; ++e) {
            uint32_t a = net->edge_nodes[2 * e], b = net->edge_nodes[2 * e + 1];
            if (a >= n || b >= n || a == b) {
                throw kr::BadArgument("edge " + std::to_string(e) + " joins nodes " +
                                      std::to_string(a) + " and " + std::to_string(b));
            }
            if (net->edge_caps[2 * e] < 0 || net->edge_caps[2 * e + 1] < 0) {
                throw kr::BadArgument("edge " + std::to_string(e) + " has a negative capacity");
            }
            add_pair(g, a, b, net->edge_caps[2 * e], net->edge_caps[2 * e + 1]);
        }
        std::vector<double> seconds;
        long flow = 0;
        std::vector<boost::default_color_type> color(n + 2);
        auto index = boost::get(boost::vertex_index, g);
        for (uint32_t k = 0; k < repeats; ++k) {
            // The algorithm sets every residual capacity from the capacity first, so each
            // repeat solves the same problem from scratch.
            auto t0 = std::chrono::steady_clock::now();
            flow = boost::boykov_kolmogorov_max_flow(
                g, boost::get(boost::edge_capacity, g), boost::get(boost::edge_residual_capacity, g),
                boost::get(boost::edge_reverse, g),
                boost::make_iterator_property_map(color.begin(), index), index, source, sink);
            auto t1 = std::chrono::steady_clock::now();
            seconds.push_back(std::chrono::duration<double>(t1 - t0).count());
        }
        std::vector<uint32_t> side(n);
        for (uint32_t i = 0; i < n; ++i) {
            // Boost documents the source tree as black: the minimum cut's source side.
            side[i] = color[i] == boost::color_traits<boost::default_color_type>::black() ? 1 : 0;
        }
        r.f64[{KR_F64_FLOW, 0}] = {static_cast<double>(flow)};
        r.f64[{KR_F64_TIMINGS, 0}] = seconds;
        r.u32[{KR_U32_FLOW_SOURCE_SIDE, 0}] = side;
    });
}
