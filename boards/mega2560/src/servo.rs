//! The board's servo axes (`axis.c.drive` / `axis.a.drive` 1,
//! `servo_encoder`): a continuous-rotation servo turning the axis, closed
//! on a quadrature encoder ([`suntracker::hw::ServoAxis`]): Chowdhury et
//! al.'s (2019) FEETECH FS5106R and YMT22 optical encoder, the Uno's
//! drive, here with the whole controller and through whatever gear the
//! configuration gives.
//!
//! | function | pin | Mega header |
//! |---|---|---|
//! | C axis servo signal (50 Hz, Timer3 OC3A) | PE3 | D5 |
//! | A axis servo signal (50 Hz, Timer3 OC3C) | PE5 | D3 |
//! | C axis encoder channels A / B (PCINT20 / 21) | PK4 / PK5 | A12 / A13 |
//! | A axis encoder channels A / B (PCINT22 / 23) | PK6 / PK7 | A14 / A15 |
//! | C / A home switch (low end, to GND, pull-up) | PC0 / PC1 | D37 / D36 |
//!
//! The encoders take the DC axes' Hall inputs and the servos the home
//! switches of every kind. Timer3 runs its 20 ms frames in every image
//! with both outputs disconnected (low, no pulse: an FS5106R without a
//! signal stays still); a servo axis's channel sends its first pulse, the
//! neutral 1,500 µs, when the axis is built
//! ([`suntracker_avr::Timer3Pwm::start_with`]). Timer3's third output,
//! OC3B (PE4, D2), is the anemometer's input and stays disconnected.
//!
//! ```text
//!  Mega D5 ─ signal ─ FS5106R (C axis; +6 V from its own supply, common GND)
//!  Mega A12 ─ encoder A   Mega A13 ─ encoder B   (YMT22, 5 V, GND)
//!  Mega D37 ─ home switch (closed at the low stop) ─ GND
//! ```
//!
//! The servo's pulses are [`suntracker::servo_tracker::SERVO`] (1,500 µs
//! stop, 700 µs and 2,300 µs full speed either way) and its position loop
//! [`suntracker::servo_tracker::POSITION_LOOP`] (full speed from 50 counts
//! out, 0.02 of it at the last count, stopping within a 20 ms frame): they
//! are the servo's and the encoder's, not the mounting's. The mounting is
//! the axis's configuration: `counts_per_motor_rev` the encoder's counts a
//! turn of its shaft (1,200 for the YMT22's 300 lines read in quadrature),
//! `microsteps` 1, `gear_ratio` the shaft's turns per axis turn.

use drivers::encoder::SharedEncoder;
use drivers::servo::ContinuousServo;
use suntracker::config::AxisConfig;
use suntracker::hw::{AnyAxis, ServoAxis};
use suntracker::servo_tracker::{POSITION_LOOP, SERVO};
use suntracker_avr::{chip, PortInputPin, Timer3Channel, Usart0};

use crate::axes::MegaAxis;
use crate::dc::DcBoard;
use crate::refused;

suntracker::progmem! {
    /// [`SERVO`] kept in flash: a constant of its 16 bytes passed to the
    /// driver by reference was a copy in the static RAM (`.data`), where
    /// this board's deepest stack leaves little.
    static SERVO_IN_FLASH: drivers::servo::ServoConfig = SERVO;
}

suntracker::progmem! {
    /// [`POSITION_LOOP`] kept in flash, as [`SERVO_IN_FLASH`].
    static LOOP_IN_FLASH: drivers::servo::PositionController = POSITION_LOOP;
}

/// A servo axis of this board: its signal on a Timer3 output, its encoder
/// counted by the pin-change interrupt, its home switch on port C.
pub type MegaServoAxis<'p> =
    ServoAxis<'static, Timer3Channel<'p>, SharedEncoder, PortInputPin<'p, chip::PORTC>>;

/// The servo axis `index` (0: C on OC3A (D5), its encoder on PK4/PK5 and
/// its home switch PC0; 1: A on OC3C (D3), PK6/PK7 and PC1), with the
/// FS5106R's pulses and the encoder's position loop; the board halted
/// (`refused`) when the servo refuses its settings (it takes these).
#[inline(never)]
pub fn servo_axis<'p>(
    board: &'p DcBoard<'p>,
    index: usize,
    config: &AxisConfig,
    log: &mut Usart0,
) -> MegaAxis<'p> {
    let parts = board.parts;
    let (oc3a, oc3c) = parts.timer3.channels();
    let (channel, encoder, home) = if index == 0 {
        (
            Timer3Channel::Oc3a(oc3a),
            parts.encoders.encoder_c(),
            suntracker_avr::InputPin::<_, 0>::new(board.portc, true).erase(),
        )
    } else {
        (
            Timer3Channel::Oc3c(oc3c),
            parts.encoders.encoder_a(),
            suntracker_avr::InputPin::<_, 1>::new(board.portc, true).erase(),
        )
    };
    match ContinuousServo::new(channel, SERVO_IN_FLASH.load()) {
        Ok(servo) => AnyAxis::ServoEncoder(ServoAxis::new(
            servo,
            encoder,
            home,
            true,
            LOOP_IN_FLASH.load(),
            config,
        )),
        Err(_) => refused(log),
    }
}
