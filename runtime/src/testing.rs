//! Helpers shared by the apps' unit tests.

use mission::moos::ProcessConfig;
use mission::source::SourceMap;

use crate::app::{Mail, Value};

/// The first `ProcessConfig` block of `text`, read as file `file`.
pub(crate) fn block(file: &str, text: &str) -> ProcessConfig {
    let src = SourceMap::from_text(file, text);
    mission::moos::parse_moos(&src).value.processes[0].clone()
}

/// Mail of `key = value` at `time` from `source`, in community `abe`.
pub(crate) fn mail(key: &str, value: Value, time: f64, source: &str) -> Mail {
    Mail {
        key: key.into(),
        value,
        time,
        source: source.into(),
        source_aux: Default::default(),
        community: "abe".into(),
    }
}
