//! Flow networks for the max-flow reference test and benchmark: random 4-connected grids with
//! segmentation-like terminal links, and conversion of katachi's networks for Boost.

use katachi::rough::FlowNetwork;

use crate::RefFlowNetwork;

/// xorshift64: deterministic, no dependency.
pub struct Rng(pub u64);

impl Rng {
    /// The next value.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// A value in `0..k`.
    pub fn below(&mut self, k: u64) -> u64 {
        self.next_u64() % k
    }
}

/// katachi's network as [`crate::boost_bk_max_flow`] takes it (the flow both links of a node
/// share, already pushed by katachi, is [`FlowNetwork::direct_flow`]).
pub fn to_reference(net: &FlowNetwork) -> RefFlowNetwork {
    let (source_caps, sink_caps) = net.terminal_capacities().unzip();
    RefFlowNetwork {
        source_caps,
        sink_caps,
        edges: net.edges().to_vec(),
    }
}

/// A `w × h` grid, 4-connected, with random edge capacities below `max_cap` (horizontal edges
/// asymmetric) and a terminal link on half of the nodes, to the source or the sink at random.
pub fn grid(w: u32, h: u32, rng: &mut Rng, max_cap: u64) -> FlowNetwork {
    let mut g = FlowNetwork::new(w * h);
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            match rng.below(4) {
                0 => g.add_terminal(i, 1 + rng.below(max_cap) as i64, 0).unwrap(),
                1 => g.add_terminal(i, 0, 1 + rng.below(max_cap) as i64).unwrap(),
                _ => {}
            }
            if x + 1 < w {
                let (a, b) = (rng.below(max_cap) as i64, rng.below(max_cap) as i64);
                g.add_edge(i, i + 1, a, b).unwrap();
            }
            if y + 1 < h {
                let c = rng.below(max_cap) as i64;
                g.add_edge(i, i + w, c, c).unwrap();
            }
        }
    }
    g
}
