//! How the debugger writes a value for the user: the engine's `print` text (integers
//! without a point, floats in the shortest text that reads back to the same double), or
//! hex for whole values when the client asks for it (DAP `ValueFormat.hex`).

use gloc_engine::program::Value;

use crate::expr::Number;

/// The largest whole float written in hex: every integer up to 2^53 is exact in a double.
const EXACT_INTEGERS: f64 = 9_007_199_254_740_992.0;

/// What the client asked for (`format` of `variables`, `evaluate`, `stackTrace`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ValueFormat {
    /// Whole values in hex (`0xc0`); fractions stay decimal, since hex digits of a
    /// double's fraction would not help anyone read it.
    pub hex: bool,
}

impl ValueFormat {
    /// An integer register, variable or element: hex is its 64 bits (two's
    /// complement, as `parse_hex` reads it back); a float that holds a whole number
    /// (a sensor such as `sci_ruhp_behs` = 192.0) is written as that integer.
    pub fn number(self, number: Number) -> String {
        match (self.hex, number) {
            (true, Number::Int(value)) => format!("0x{:x}", value as u64),
            (true, Number::Float(value)) => whole(value).map_or_else(
                || Value::Float(value).to_string(),
                |whole| self.number(Number::Int(whole)),
            ),
            (false, number) => number.to_string(),
        }
    }

    /// A sensor (always a double).
    pub fn sensor(self, value: f64) -> String {
        self.number(Number::Float(value))
    }

    /// A count the debugger shows (a pc, a cycle).
    pub fn count(self, value: usize) -> String {
        if self.hex {
            format!("0x{value:x}")
        } else {
            value.to_string()
        }
    }
}

/// Reads what the hex format shows back (`0xc0`, `0xffffffffffffffff` = -1, `-0x10`):
/// an integer's 64 bits. `None` for anything else (GBASIC has no hex literals, so a
/// value typed in the Variables view is tried as hex first, then as an expression).
pub fn parse_hex(text: &str) -> Option<Number> {
    let text = text.trim();
    let (negative, unsigned) = match text.strip_prefix('-') {
        Some(rest) => (true, rest.trim_start()),
        None => (false, text),
    };
    let digits = unsigned
        .strip_prefix("0x")
        .or_else(|| unsigned.strip_prefix("0X"))?;
    let value = u64::from_str_radix(digits, 16).ok()? as i64;
    Some(Number::Int(if negative {
        value.wrapping_neg()
    } else {
        value
    }))
}

/// The float as an integer when it is a whole number that a double holds exactly.
fn whole(value: f64) -> Option<i64> {
    (value.fract() == 0.0 && value.abs() <= EXACT_INTEGERS).then_some(value as i64)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEX: ValueFormat = ValueFormat { hex: true };

    #[test]
    fn decimal_is_the_print_text() {
        let plain = ValueFormat::default();
        assert_eq!(plain.number(Number::Int(-7)), "-7");
        assert_eq!(plain.number(Number::Float(15.0)), "15.0");
        assert_eq!(
            plain.number(Number::Float(0.1 + 0.2)),
            "0.30000000000000004"
        );
        assert_eq!(plain.sensor(1e-7), "1e-7");
        // The shortest text reads back to the same bits.
        for value in [15.037499999999937, 0.1 + 0.2, 1.0 / 3.0, -2.5e-300] {
            let text = plain.sensor(value);
            assert_eq!(text.parse::<f64>().map(f64::to_bits), Ok(value.to_bits()));
        }
    }

    #[test]
    fn hex_shows_the_bits_of_whole_values_only() {
        // sci_ruhp_behs = 192: bits 64 and 128 (Fig. 3 sets 128, the climb 64).
        assert_eq!(HEX.sensor(192.0), "0xc0");
        assert_eq!(HEX.number(Number::Int(128)), "0x80");
        assert_eq!(HEX.number(Number::Int(-1)), "0xffffffffffffffff");
        assert_eq!(HEX.number(Number::Int(0)), "0x0");
        assert_eq!(HEX.sensor(-16.0), "0xfffffffffffffff0");
        assert_eq!(HEX.sensor(2.5), "2.5");
        assert_eq!(HEX.sensor(1e300), "1e300");
        assert_eq!(HEX.sensor(f64::NAN), "NaN");
        assert_eq!(HEX.count(31), "0x1f");
        // What hex shows reads back as the same integer.
        for value in [0, 1, 192, -1, -16, i64::MIN, i64::MAX] {
            let text = HEX.number(Number::Int(value));
            assert_eq!(parse_hex(&text), Some(Number::Int(value)), "{text}");
        }
        assert_eq!(parse_hex("-0x10"), Some(Number::Int(-16)));
        assert_eq!(parse_hex("0XFF"), Some(Number::Int(255)));
        for not_hex in ["12", "0x", "0xg", "0x1ffffffffffffffff", "x10", ""] {
            assert_eq!(parse_hex(not_hex), None, "{not_hex}");
        }
    }
}
