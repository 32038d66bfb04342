//! RINEX files parsed from their decompressed bytes: the epoch records of RINEX 2.xx and 3.xx/4.xx
//! observation files (`obs_body`) and whole navigation files of RINEX 2.xx, 3.xx and 4.xx (`nav`).
//! Opening, Hatanaka decompression, the observation header and the choice of codes stay in Python
//! (`gnssatt.rinex`); these modules walk the records, check every field and fill flat arrays.
//!
//! The reader is strict about malformed records (an error names the 1-based line, what was expected and
//! what came) and generous about valid ones; its messages quote the file's text the way Python's `repr`
//! does, so that they read the same as the rest of the package's (`text`).

mod epoch;
mod lines;
pub mod nav;
pub mod obs_body;
mod obs_fields;
mod text;

pub use nav::{read_nav, NavRecords, NavSkip, GLONASS_VALUES, KEPLER_VALUES};
pub use obs_body::{read_obs_body, BodyError, BodyOptions, ObsBody, SystemLayout};
