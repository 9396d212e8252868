//! The NC-program correction end to end: the interpreter of `trueaxis-nc` under
//! the pose corrector, checked against LinuxCNC's rs274 and readers written here.
//!
//! [`linuxcnc_samples`]: LinuxCNC's own sample programs; [`rs274`]: programs written for this, run
//! by rs274; [`fanuc`]: Fanuc-style CAM and macro programs; [`fadal`]: Fadal format 2 programs; [`siemens`]: SINUMERIK 840D programs in
//! its own language; [`roundtrip`]: examples read back
//! through the erroneous machine, closed forms; [`bad_programs`]: refusals.

mod bad_programs;
mod common;
mod corpus;
mod fadal;
mod fanuc;
mod linuxcnc_samples;
mod parts;
mod posts;
mod reading;
mod roundtrip;
mod rs274;
mod siemens;
mod splines;
