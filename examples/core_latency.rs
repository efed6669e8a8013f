//! How long one core takes to see another core's write: two threads pass a counter back and forth
//! through one atomic value, and the round trips' mean time is halved. On the project's 2-core
//! virtual machines it tells whether the host has placed the two cores where they share a cache
//! (25–70 ns) or not (140–240 ns), which decides how much a run on two threads gains from keeping
//! each disk on one thread (docs/performance.md, "Who does the parts").
//!
//! `cargo run --release --example core_latency [ROUND_TRIPS]` (default 200 000) prints
//! `one_way_ns=…`. Run it on an otherwise idle machine: the two threads must have a core each.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

fn main() {
    let trips: u64 = std::env::args().nth(1).map_or(200_000, |n| n.parse().expect("usage: core_latency [ROUND_TRIPS]"));
    let counter = Arc::new(AtomicU64::new(0));
    let other = Arc::clone(&counter);
    let echo = std::thread::spawn(move || {
        for k in 0..trips {
            while other.load(Ordering::SeqCst) != 2 * k + 1 {
                std::hint::spin_loop();
            }
            other.store(2 * k + 2, Ordering::SeqCst);
        }
    });
    let start = Instant::now();
    for k in 0..trips {
        counter.store(2 * k + 1, Ordering::SeqCst);
        while counter.load(Ordering::SeqCst) != 2 * k + 2 {
            std::hint::spin_loop();
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    echo.join().expect("the echoing thread ends");
    println!("one_way_ns={:.0}", seconds * 1e9 / (2 * trips) as f64);
}
