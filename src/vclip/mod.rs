//! V-Clip (Mirtich 1998) with the deepest-vertex search.
