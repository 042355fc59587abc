//! The half-duplex line against a model of a UART with a transmit data
//! register and a shift register (as RM0383 §19.3.2 describes the STM32's
//! USART: TXE when the data register has passed its byte to the shift
//! register, TC when the shift register has sent its last stop bit and the
//! data register is empty), one character time per step.

use suntracker_modbus::{HalfDuplexLine, UartIo};

#[derive(Default)]
struct ModelUart {
    data: Option<u8>,
    shift: Option<u8>,
    sent_any: bool,
    txe_ie: bool,
    tc_ie: bool,
    driver: bool,
    /// What the receiver holds: a byte, or a damaged one.
    received: Option<Result<u8, ()>>,
    /// Each byte that left the shift register, with the driver's state
    /// while it did.
    wire: Vec<(u8, bool)>,
    /// The driver's state at each step.
    driver_trace: Vec<bool>,
}

impl UartIo for ModelUart {
    fn take_received(&mut self) -> Option<Result<u8, ()>> {
        self.received.take()
    }
    fn tx_empty(&mut self) -> bool {
        self.data.is_none()
    }
    fn write(&mut self, byte: u8) {
        assert!(
            self.data.is_none(),
            "a byte written over a full data register"
        );
        self.data = Some(byte);
    }
    fn tx_complete(&mut self) -> bool {
        self.sent_any && self.data.is_none() && self.shift.is_none()
    }
    fn set_tx_interrupts(&mut self, empty: bool, complete: bool) {
        self.txe_ie = empty;
        self.tc_ie = complete;
    }
    fn set_driver(&mut self, on: bool) {
        self.driver = on;
    }
}

impl ModelUart {
    fn interrupt_pending(&mut self) -> bool {
        self.received.is_some()
            || (self.txe_ie && self.data.is_none())
            || (self.tc_ie && self.tx_complete())
    }
    /// One character time: the shift register sends its byte and takes
    /// the data register's.
    fn step(&mut self) {
        if let Some(b) = self.shift.take() {
            self.wire.push((b, self.driver));
            self.sent_any = true;
        }
        self.shift = self.data.take();
        self.driver_trace.push(self.driver);
    }
}

/// Runs the UART until nothing is pending and the shift register is empty
/// (at most `steps` character times), serving every pending interrupt.
fn run(line: &mut HalfDuplexLine<16>, uart: &mut ModelUart, steps: usize) {
    for t in 0..steps {
        while uart.interrupt_pending() {
            line.on_interrupt(uart, t as u32 * 573);
        }
        uart.step();
    }
}

#[test]
fn a_reply_goes_out_whole_with_the_driver_on_and_then_released() {
    let mut line = HalfDuplexLine::<16>::new();
    let mut uart = ModelUart::default();
    let frame = [0x01, 0x03, 0x02, 0x53, 0x75, 0xA4, 0x2F];
    line.start_send(&mut uart, &frame);
    assert!(line.busy());
    assert!(uart.driver);
    run(&mut line, &mut uart, 20);
    let bytes: Vec<u8> = uart.wire.iter().map(|&(b, _)| b).collect();
    assert_eq!(bytes, frame);
    assert!(
        uart.wire.iter().all(|&(_, driven)| driven),
        "{:?}",
        uart.wire
    );
    // Released, and nothing left enabled.
    assert!(!uart.driver);
    assert!(!line.busy());
    assert!(!uart.txe_ie && !uart.tc_ie);
    // Released only after the last byte left: the driver was on for the
    // frame's 7 character times and one more (the first byte's way into
    // the shift register), then off.
    let on = uart.driver_trace.iter().filter(|&&d| d).count();
    assert_eq!(on, frame.len() + 1, "{:?}", uart.driver_trace);
}

#[test]
fn the_longest_frame_is_sent_and_a_longer_one_cut() {
    let mut line = HalfDuplexLine::<16>::new();
    let mut uart = ModelUart::default();
    let frame: Vec<u8> = (0..300u32).map(|i| i as u8).collect();
    line.start_send(&mut uart, &frame);
    run(&mut line, &mut uart, 400);
    assert_eq!(uart.wire.len(), 256);
    assert!(uart.wire.iter().zip(&frame).all(|(&(b, _), &f)| b == f));
    assert!(!line.busy() && !uart.driver);
}

#[test]
fn an_empty_reply_drives_nothing() {
    let mut line = HalfDuplexLine::<16>::new();
    let mut uart = ModelUart::default();
    line.start_send(&mut uart, &[]);
    assert!(!line.busy() && !uart.driver && !uart.txe_ie);
}

#[test]
fn bytes_are_queued_with_their_times_and_dropped_while_sending() {
    let mut line = HalfDuplexLine::<16>::new();
    let mut uart = ModelUart {
        received: Some(Ok(0x11)),
        ..ModelUart::default()
    };
    line.on_interrupt(&mut uart, 100);
    uart.received = Some(Err(()));
    line.on_interrupt(&mut uart, 200);
    uart.received = Some(Ok(0x22));
    line.on_interrupt(&mut uart, 300);
    assert_eq!(line.receive(), Some((0x11, 100)));
    assert_eq!(line.receive(), Some((0x22, 300)));
    assert_eq!(line.receive(), None);
    assert_eq!(
        (line.received().received(), line.received().dropped()),
        (3, 1)
    );
    // Queued before the reply: forgotten when it starts. Received while
    // it goes out: dropped.
    uart.received = Some(Ok(0x33));
    line.on_interrupt(&mut uart, 400);
    line.start_send(&mut uart, &[1, 2, 3]);
    uart.received = Some(Ok(0x44));
    line.on_interrupt(&mut uart, 500);
    run(&mut line, &mut uart, 10);
    assert_eq!(line.receive(), None);
    // Receiving again after the release.
    uart.received = Some(Ok(0x55));
    line.on_interrupt(&mut uart, 9_000);
    assert_eq!(line.receive(), Some((0x55, 9_000)));
}
