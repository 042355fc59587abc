//! Gray-code quadrature decoding. Forward (A leads B): 00 → 10 → 11 → 01 → 00.

use drivers::encoder::{
    transition, AtomicEncoder, PolledEncoder, QuadratureDecoder, SharedEncoder, Transition,
};
use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
use embedded_hal_mock::eh1::MockError;

/// (A, B) levels of one forward cycle.
const CYCLE: [(bool, bool); 4] = [(false, false), (true, false), (true, true), (false, true)];

#[test]
fn full_table() {
    use Transition::*;
    // Written out from the Gray sequence, states (A<<1)|B: 0=00, 1=01, 2=10, 3=11.
    let expect = [
        (0, 0, None),
        (0, 2, Forward),
        (2, 3, Forward),
        (3, 1, Forward),
        (1, 0, Forward),
        (0, 1, Backward),
        (1, 3, Backward),
        (3, 2, Backward),
        (2, 0, Backward),
        (0, 3, Illegal),
        (3, 0, Illegal),
        (1, 2, Illegal),
        (2, 1, Illegal),
        (1, 1, None),
        (2, 2, None),
        (3, 3, None),
    ];
    for (p, c, t) in expect {
        assert_eq!(transition(p, c), t, "{p} -> {c}");
    }
}

#[test]
fn counts_cycles_both_ways_and_errors() {
    let mut d = QuadratureDecoder::new(false, false);
    // 300 pulses per revolution: one revolution = 300 cycles = 1200 counts.
    for _ in 0..300 {
        for &(a, b) in CYCLE.iter().skip(1).chain(CYCLE.iter().take(1)) {
            d.update(a, b);
        }
    }
    assert_eq!(d.count(), 1_200);
    for _ in 0..75 {
        for &(a, b) in CYCLE.iter().rev() {
            d.update(a, b);
        }
    }
    assert_eq!(d.count(), 900);
    // A missed edge: 00 -> 11 is illegal, counted as an error, count unchanged.
    assert_eq!(d.update(true, true), Transition::Illegal);
    assert_eq!((d.count(), d.errors()), (900, 1));
    // Decoding continues from the new state: 11 -> 01 is forward.
    assert_eq!(d.update(false, true), Transition::Forward);
    assert_eq!(d.count(), 901);
}

static SHARED: SharedEncoder = SharedEncoder::new();
static ATOMIC: AtomicEncoder = AtomicEncoder::new();

#[test]
fn interrupt_shared_counters() {
    // "Interrupt" thread feeds edges while the main thread reads.
    SHARED.set_levels(false, false);
    let isr = std::thread::spawn(|| {
        for i in 0..4_000usize {
            let (a, b) = CYCLE[(i + 1) % 4];
            SHARED.update(a, b);
            ATOMIC.update(a, b);
        }
    });
    let mut last = 0;
    while !isr.is_finished() {
        let c = SHARED.count();
        assert!(c >= last, "count never goes backward for forward motion");
        last = c;
    }
    isr.join().unwrap();
    assert_eq!((SHARED.count(), SHARED.errors()), (4_000, 0));
    assert_eq!((ATOMIC.count(), ATOMIC.errors()), (4_000, 0));
    SHARED.update(false, true); // 00 -> 01: backward
    ATOMIC.update(true, true); // 00 -> 11: illegal
    assert_eq!(SHARED.count(), 3_999);
    assert_eq!(ATOMIC.errors(), 1);
    SHARED.set_count(0);
    assert_eq!(SHARED.count(), 0);
}

#[test]
fn polled_pins_exact_reads() {
    use State::{High as H, Low as L};
    // Start 00; then 10 (forward), 11 (forward), 00 (illegal), and a read error on A.
    let a = Pin::new(&[
        T::get(L),
        T::get(H),
        T::get(H),
        T::get(L),
        T::get(L).with_error(MockError::Io(std::io::ErrorKind::Other)),
    ]);
    let b = Pin::new(&[T::get(L), T::get(L), T::get(H), T::get(L)]);
    let mut e = PolledEncoder::new(a, b).unwrap();
    assert_eq!(e.poll().unwrap(), Transition::Forward);
    assert_eq!(e.poll().unwrap(), Transition::Forward);
    assert_eq!(e.poll().unwrap(), Transition::Illegal);
    assert!(e.poll().is_err());
    assert_eq!((e.decoder().count(), e.decoder().errors()), (2, 1));
    let (mut a, mut b) = e.destroy();
    a.done();
    b.done();
}
