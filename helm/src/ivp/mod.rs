//! IvP core (issue #2).
