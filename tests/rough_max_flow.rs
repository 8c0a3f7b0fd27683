//! The Boykov–Kolmogorov max-flow (`katachi::rough::FlowNetwork`, seed 003 §3's solver)
//! against Edmonds–Karp written plainly here on random small networks: the same flow and the
//! same minimum-cut labels (the minimal source side, which every maximum flow shares). Boost's
//! own BK on large grids and band graphs is in `tests/reference/tests/max_flow.rs`.

mod support;

use katachi::rough::{FlowNetwork, MAX_CAPACITY, MAX_TOTAL_CAPACITY};
use proptest::prelude::*;
use support::property::counted_proptest;

/// Edmonds–Karp on a dense matrix: flow and the nodes reachable from the source at the end.
fn edmonds_karp(src: &[i64], snk: &[i64], edges: &[(u32, u32, i64, i64)]) -> (i64, Vec<bool>) {
    let n = src.len();
    let (s, t, m) = (n, n + 1, n + 2);
    let mut c = vec![vec![0i64; m]; m];
    for i in 0..n {
        c[s][i] += src[i];
        c[i][t] += snk[i];
    }
    for &(a, b, ab, ba) in edges {
        c[a as usize][b as usize] += ab;
        c[b as usize][a as usize] += ba;
    }
    let mut flow = 0;
    loop {
        let mut prev = vec![usize::MAX; m];
        prev[s] = s;
        let mut queue = std::collections::VecDeque::from([s]);
        while let Some(u) = queue.pop_front() {
            for v in 0..m {
                if prev[v] == usize::MAX && c[u][v] > 0 {
                    prev[v] = u;
                    queue.push_back(v);
                }
            }
        }
        if prev[t] == usize::MAX {
            return (flow, (0..n).map(|i| prev[i] != usize::MAX).collect());
        }
        let mut b = i64::MAX;
        let mut v = t;
        while v != s {
            b = b.min(c[prev[v]][v]);
            v = prev[v];
        }
        let mut v = t;
        while v != s {
            c[prev[v]][v] -= b;
            c[v][prev[v]] += b;
            v = prev[v];
        }
        flow += b;
    }
}

type Net = (Vec<(i64, i64)>, Vec<(u32, u32, i64, i64)>);

/// A random network of 2–24 nodes: terminal links on some nodes (some with both), edges
/// between random pairs with capacities up to `max_cap` each way (parallel edges allowed).
fn network(max_cap: i64) -> impl Strategy<Value = Net> {
    (2u32..24).prop_flat_map(move |n| {
        let link = prop_oneof![Just(0i64), 1..=max_cap];
        (
            prop::collection::vec((link.clone(), link), n as usize),
            prop::collection::vec((0..n, 0..n, 0..=max_cap, 0..=max_cap), 0..4 * n as usize),
        )
    })
}

fn check(net: &Net) -> Result<(), TestCaseError> {
    let (terminals, edges) = net;
    let mut g = FlowNetwork::new(terminals.len() as u32);
    for (i, &(s, t)) in terminals.iter().enumerate() {
        g.add_terminal(i as u32, s, t).unwrap();
    }
    let edges: Vec<_> = edges.iter().copied().filter(|e| e.0 != e.1).collect();
    for &(a, b, ab, ba) in &edges {
        g.add_edge(a, b, ab, ba).unwrap();
    }
    let src: Vec<i64> = terminals.iter().map(|t| t.0).collect();
    let snk: Vec<i64> = terminals.iter().map(|t| t.1).collect();
    let (flow, side) = edmonds_karp(&src, &snk, &edges);
    let a = g.clone().solve();
    prop_assert_eq!(a.flow, flow);
    prop_assert_eq!(&a.source_side, &side);
    // The same bits on a second run.
    prop_assert_eq!(g.solve(), a);
    Ok(())
}

counted_proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn small_capacities_match_edmonds_karp(net in network(12)) {
        check(&net)?;
    }

    #[test]
    fn capacities_past_32_bits_match_edmonds_karp(net in network(1 << 45)) {
        check(&net)?;
    }
}

#[test]
fn a_path_with_both_links_on_one_node() {
    // Node 0 has 5 from the source and 2 to the sink: 2 go straight through.
    let mut g = FlowNetwork::new(2);
    g.add_terminal(0, 5, 2).unwrap();
    g.add_terminal(1, 0, 7).unwrap();
    g.add_edge(0, 1, 1, 0).unwrap();
    assert_eq!(g.direct_flow(), 2);
    let cut = g.solve();
    assert_eq!(cut.flow, 3);
    assert_eq!(cut.source_side, vec![true, false]);
}

#[test]
fn bad_nodes_and_capacities_are_refused() {
    let mut g = FlowNetwork::new(2);
    for r in [
        g.add_edge(0, 2, 1, 1),
        g.add_edge(1, 1, 1, 1),
        g.add_edge(0, 1, -1, 1),
        g.add_edge(0, 1, 1, MAX_CAPACITY + 1),
        g.add_terminal(5, 1, 1),
        g.add_terminal(0, -1, 0),
        g.add_terminal(0, 1, MAX_CAPACITY + 1),
    ] {
        let e = r.unwrap_err();
        assert_eq!(e.kind(), katachi::ErrorKind::BadInput, "{e}");
        assert!(e.to_string().contains("flow network"), "{e}");
    }
    // The totals are bounded too, and a refused call changes nothing.
    let mut g = FlowNetwork::new(1 << 10);
    let mut added = 0;
    for i in 0..1 << 10 {
        if g.add_terminal(i, MAX_CAPACITY, 0).is_ok() {
            added += 1;
        }
    }
    assert_eq!(added, MAX_TOTAL_CAPACITY / MAX_CAPACITY);
    assert_eq!(g.edge_count(), 0);
    let cut = g.solve();
    assert_eq!(cut.flow, 0);
}
