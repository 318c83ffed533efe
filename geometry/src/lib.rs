//! XY geometry for the helm and viewer: points, segment lists, polygons, and MOOS-IvP's
//! geometry strings (point patterns, `VIEW_POINT` / `VIEW_SEGLIST` / `VIEW_POLYGON` specs).
