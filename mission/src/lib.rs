//! Mission files: the nsplug preprocessor and the `.moos` and `.bhv` parsers.
//!
//! Filled by issue #3.
