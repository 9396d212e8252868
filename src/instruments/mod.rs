//! Measurement equations and reductions of instruments: reversal techniques, scale thermal
//! expansion (later: 3D ball, lengths, probing).
