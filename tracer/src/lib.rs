//! A Whitted ray tracer built on vecexpr.
