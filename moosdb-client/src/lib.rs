//! The MOOS wire protocol: packet codec, async client and an embedded MOOSDB server.
//!
//! Filled by issue #6.
