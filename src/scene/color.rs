//! Colours as scenes write them.

/// A straight (not premultiplied) RGBA colour, 8 bits per channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rgba(pub [u8; 4]);

impl Rgba {
    pub const WHITE: Rgba = Rgba([255, 255, 255, 255]);
    pub const BLACK: Rgba = Rgba([0, 0, 0, 255]);

    /// Parses `#rgb`, `#rrggbb`, `#rrggbbaa` or one of a few common names.
    pub fn parse(s: &str) -> Option<Rgba> {
        let named = match s {
            "white" => Some("#ffffff"),
            "black" => Some("#000000"),
            "red" => Some("#d62728"),
            "green" => Some("#2ca02c"),
            "blue" => Some("#1f77b4"),
            "orange" => Some("#ff7f0e"),
            "purple" => Some("#9467bd"),
            "grey" | "gray" => Some("#7f7f7f"),
            "transparent" => Some("#00000000"),
            _ => None,
        };
        let hex = named.unwrap_or(s).strip_prefix('#')?;
        if !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        let channel = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).ok();
        match hex.len() {
            3 => {
                let mut c = [255u8; 4];
                for (i, ch) in hex.chars().enumerate() {
                    let v = ch.to_digit(16)? as u8;
                    c[i] = v * 17;
                }
                Some(Rgba(c))
            }
            6 => Some(Rgba([channel(0)?, channel(2)?, channel(4)?, 255])),
            8 => Some(Rgba([channel(0)?, channel(2)?, channel(4)?, channel(6)?])),
            _ => None,
        }
    }

    /// Returns the colour for body number `i` when the scene names none: the ten
    /// colours of matplotlib's default cycle, which stay distinct for most viewers.
    pub fn palette(i: usize) -> Rgba {
        const CYCLE: [[u8; 3]; 10] = [
            [0x1f, 0x77, 0xb4],
            [0xff, 0x7f, 0x0e],
            [0x2c, 0xa0, 0x2c],
            [0xd6, 0x27, 0x28],
            [0x94, 0x67, 0xbd],
            [0x8c, 0x56, 0x4b],
            [0xe3, 0x77, 0xc2],
            [0x7f, 0x7f, 0x7f],
            [0xbc, 0xbd, 0x22],
            [0x17, 0xbe, 0xcf],
        ];
        let [r, g, b] = CYCLE[i % CYCLE.len()];
        Rgba([r, g, b, 255])
    }
}

#[cfg(test)]
mod tests {
    use super::Rgba;

    #[test]
    fn parses_every_written_form() {
        assert_eq!(Rgba::parse("#cc3333"), Some(Rgba([0xcc, 0x33, 0x33, 255])));
        assert_eq!(Rgba::parse("#f00"), Some(Rgba([255, 0, 0, 255])));
        assert_eq!(
            Rgba::parse("#11223344"),
            Some(Rgba([0x11, 0x22, 0x33, 0x44]))
        );
        assert_eq!(Rgba::parse("white"), Some(Rgba::WHITE));
        assert_eq!(Rgba::parse("cc3333"), None);
        assert_eq!(Rgba::parse("#cc333"), None);
        assert_eq!(Rgba::parse("#gg0000"), None);
        assert_eq!(Rgba::parse("#é00"), None);
    }
}
