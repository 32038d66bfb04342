//! RINEX observation bodies: the epoch records of RINEX 2.xx and 3.xx/4.xx observation files, parsed from
//! the decompressed bytes of the file. The header, Hatanaka decompression and the choice of codes stay in
//! Python (`gnssatt.rinex`); this module walks the epochs, checks every field and fills the dense arrays.
//!
//! The reader is strict about malformed records (an error names the 1-based line, what was expected and
//! what came) and generous about valid ones; its messages quote the file's text the way Python's `repr`
//! does, so that they read the same as the rest of the package's (`text`).

mod epoch;
mod lines;
pub mod obs_body;
mod obs_fields;
mod text;

pub use obs_body::{read_obs_body, BodyError, BodyOptions, ObsBody, SystemLayout};
