// Test support for the DS1302 examples in src/rtc/ds1302.rs (pulled in with
// `include!`, not a module of the crate): expands command and data bytes into
// the exact pin transactions of the Maxim DS1302 datasheet (19-5420), "Data
// Transfer Summary": SCLK low before CE rises; bytes LSB first, each bit set
// on I/O before a rising SCLK edge; on a read, I/O is released after the
// eighth command clock's rising edge and the chip drives each data bit from
// the falling edge before it; CE low ends the transfer.

use embedded_hal_mock::eh1::delay::NoopDelay;
use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};

/// The expected transactions of CE, SCLK and I/O.
#[derive(Default)]
pub struct Wire {
    ce: Vec<T>,
    clk: Vec<T>,
    io: Vec<T>,
}

fn level(bit: bool) -> State {
    if bit {
        State::High
    } else {
        State::Low
    }
}

impl Wire {
    fn send(&mut self, byte: u8, release_last: bool) {
        for bit in 0..8 {
            self.io.push(T::set(level(byte >> bit & 1 == 1)));
            self.clk.push(T::set(State::High));
            if bit == 7 && release_last {
                self.io.push(T::set(State::High));
            }
            self.clk.push(T::set(State::Low));
        }
    }

    /// A write transfer: command byte, then the data bytes.
    pub fn write(&mut self, command: u8, data: &[u8]) {
        self.clk.push(T::set(State::Low));
        self.ce.push(T::set(State::High));
        self.send(command, false);
        for &b in data {
            self.send(b, false);
        }
        self.ce.push(T::set(State::Low));
    }

    /// A read transfer: command byte, then the chip drives `data`.
    pub fn read(&mut self, command: u8, data: &[u8]) {
        self.clk.push(T::set(State::Low));
        self.ce.push(T::set(State::High));
        self.send(command, true);
        for &b in data {
            for bit in 0..8 {
                self.io.push(T::get(level(b >> bit & 1 == 1)));
                self.clk.push(T::set(State::High));
                self.clk.push(T::set(State::Low));
            }
        }
        self.ce.push(T::set(State::Low));
    }

    /// The three pin mocks and a delay, in `Ds1302::new`'s order.
    pub fn pins(&self) -> (Pin, Pin, Pin, NoopDelay) {
        (
            Pin::new(&self.ce),
            Pin::new(&self.clk),
            Pin::new(&self.io),
            NoopDelay::new(),
        )
    }
}

/// Checks that every expected transaction took place.
pub fn done(pins: (Pin, Pin, Pin, NoopDelay)) {
    let (mut ce, mut clk, mut io, _) = pins;
    ce.done();
    clk.done();
    io.done();
}
