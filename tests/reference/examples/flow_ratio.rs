//! Quick side-by-side: katachi's max-flow and Boost's, alternating, on the bench's grid.
use std::time::Instant;

use katachi_reference::boost_bk_max_flow;
use katachi_reference::flow_graphs::{grid, to_reference, Rng};

fn main() {
    let n: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1000);
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let net = grid(n, n, &mut rng, 1 << 16);
    let reference = to_reference(&net);
    for _ in 0..3 {
        let g = net.clone();
        let t = Instant::now();
        let cut = g.solve();
        let ours = t.elapsed();
        let b = boost_bk_max_flow(&reference, 1).unwrap();
        println!(
            "katachi {:?} boost {:?} ratio {:.3} (flow {} {})",
            ours,
            b.times[0],
            ours.as_secs_f64() / b.times[0].as_secs_f64(),
            cut.flow,
            b.flow + net.direct_flow()
        );
    }
}
