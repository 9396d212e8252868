//! Screening (`trueaxis::screen`) against damaged variants of the shipped examples: each damage,
//! made by [`damage`] (one per file, at several sizes), is refused or flagged with the file, the
//! run, column or lines and the kind named; the clean examples give no finding; the false-alarm
//! rate on simulated clean data stays under 1 % per check.

mod ballbar;
mod campaign;
mod damage;
mod false_alarms;
mod positioning;
mod robust;
mod thermal;
