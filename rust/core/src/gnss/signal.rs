//! Satellite systems, satellite identifiers and carrier frequencies.
//!
//! Each system has up to [`MAX_FREQUENCIES`] frequency slots, numbered as RTKLIB numbers them where it
//! can (so that `--frequencies 2` selects the same signals as `rnx2rtkp -f 2`):
//!
//! | slot | GPS | GLONASS (FDMA, channel k) | Galileo | BeiDou | QZSS |
//! |---|---|---|---|---|---|
//! | 0 | L1 1575.42 | G1 1602 + 0.5625 k | E1 1575.42 | B1I 1561.098 | L1 1575.42 |
//! | 1 | L2 1227.60 | G2 1246 + 0.4375 k | E5b 1207.14 | B2I/B2b 1207.14 | L2 1227.60 |
//! | 2 | L5 1176.45 | G3 1202.025 | E5a 1176.45 | B3I 1268.52 | L5 1176.45 |
//!
//! (MHz; IS-GPS-200/705, GLONASS ICD 5.1, Galileo OS SIS ICD 2.0, BDS-SIS-ICD-B1I 3.0 / B3I 1.0,
//! IS-QZSS-PNT.) BeiDou slot 2 is B3I here, where RTKLIB 2.4.3 puts B2a.

use std::fmt;

/// Frequency slots per system.
pub const MAX_FREQUENCIES: usize = 3;

/// Speed of light in vacuum, m/s (IS-GPS-200).
pub const SPEED_OF_LIGHT_M_S: f64 = 299_792_458.0;

/// A satellite navigation system.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum System {
    Gps,
    Glonass,
    Galileo,
    BeiDou,
    Qzss,
}

impl System {
    /// Every system, in the order of [`System::index`].
    pub const ALL: [System; 5] = [
        System::Gps,
        System::Glonass,
        System::Galileo,
        System::BeiDou,
        System::Qzss,
    ];

    /// The RINEX system letter (`G`, `R`, `E`, `C`, `J`).
    pub fn letter(self) -> char {
        match self {
            System::Gps => 'G',
            System::Glonass => 'R',
            System::Galileo => 'E',
            System::BeiDou => 'C',
            System::Qzss => 'J',
        }
    }

    /// The system of a RINEX letter, if it is one of the five.
    pub fn from_letter(c: char) -> Option<System> {
        System::ALL.into_iter().find(|s| s.letter() == c)
    }

    /// Position in [`System::ALL`] (0..5), for per-system arrays.
    pub fn index(self) -> usize {
        match self {
            System::Gps => 0,
            System::Glonass => 1,
            System::Galileo => 2,
            System::BeiDou => 3,
            System::Qzss => 4,
        }
    }

    /// Name of each slot's signal (see the module table).
    pub fn slot_names(self) -> [&'static str; MAX_FREQUENCIES] {
        match self {
            System::Gps | System::Qzss => ["L1", "L2", "L5"],
            System::Glonass => ["G1", "G2", "G3"],
            System::Galileo => ["E1", "E5b", "E5a"],
            System::BeiDou => ["B1I", "B2I", "B3I"],
        }
    }
}

/// A satellite: system and PRN (slot number for GLONASS).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SatId {
    pub system: System,
    pub prn: u8,
}

impl fmt::Display for SatId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{:02}", self.system.letter(), self.prn)
    }
}

/// Carrier frequency of `slot` of `system`, Hz; `None` where the slot has no signal or a GLONASS FDMA
/// slot (G1, G2) is asked without a channel number in -7..=6.
pub fn carrier_frequency_hz(
    system: System,
    slot: usize,
    glonass_channel: Option<i8>,
) -> Option<f64> {
    const MHZ: f64 = 1e6;
    let f = match (system, slot) {
        (System::Gps | System::Qzss, 0) | (System::Galileo, 0) => 1575.42 * MHZ,
        (System::Gps | System::Qzss, 1) => 1227.60 * MHZ,
        (System::Gps | System::Qzss, 2) | (System::Galileo, 2) => 1176.45 * MHZ,
        (System::Galileo, 1) | (System::BeiDou, 1) => 1207.14 * MHZ,
        (System::BeiDou, 0) => 1561.098 * MHZ,
        (System::BeiDou, 2) => 1268.52 * MHZ,
        (System::Glonass, 2) => 1202.025 * MHZ,
        (System::Glonass, 0 | 1) => {
            let k = f64::from(glonass_channel.filter(|k| (-7..=6).contains(k))?);
            if slot == 0 {
                1602.0 * MHZ + 0.5625 * MHZ * k
            } else {
                1246.0 * MHZ + 0.4375 * MHZ * k
            }
        }
        _ => return None,
    };
    Some(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wavelengths_match_the_icd_values() {
        // L1 wavelength 0.190293672798 m (IS-GPS-200: c / 1575.42 MHz).
        let l1 = SPEED_OF_LIGHT_M_S / carrier_frequency_hz(System::Gps, 0, None).unwrap();
        assert!((l1 - 0.190_293_672_798).abs() < 1e-12);
        // GLONASS G1 channel -7 and +6 (ICD 5.1, table 2.1): 1598.0625 and 1605.375 MHz.
        assert_eq!(
            carrier_frequency_hz(System::Glonass, 0, Some(-7)),
            Some(1598.0625e6)
        );
        assert_eq!(
            carrier_frequency_hz(System::Glonass, 0, Some(6)),
            Some(1605.375e6)
        );
        assert_eq!(carrier_frequency_hz(System::Glonass, 0, None), None);
        assert_eq!(carrier_frequency_hz(System::Glonass, 1, Some(7)), None);
        assert_eq!(carrier_frequency_hz(System::Gps, 3, None), None);
        for s in System::ALL {
            assert_eq!(System::from_letter(s.letter()), Some(s));
            assert_eq!(System::ALL[s.index()], s);
        }
    }
}
