//! Raw simavr speed on an ELF: `cargo run --release -p suntracker-emu --example speed -- ELF [cycles]`.
fn main() {
    let mut args = std::env::args().skip(1);
    let elf = args.next().expect("ELF");
    let cycles: u64 = args.next().map_or(40_000_000, |c| c.parse().unwrap());
    let mut sim = suntracker_emu::sim::Sim::new("atmega2560", 16_000_000, elf.as_ref()).unwrap();
    sim.attach_uart('0').unwrap();
    let t = std::time::Instant::now();
    let state = sim.run_until(cycles);
    let wall = t.elapsed();
    println!(
        "{} cycles in {:?} ({:.1} M cycles/s), {:?}",
        sim.cycle(),
        wall,
        sim.cycle() as f64 / wall.as_secs_f64() / 1e6,
        state
    );
}
