//! Integration tests of xhab-sim, one binary (topic files below).
mod geodesic_closed_form;
