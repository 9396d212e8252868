//! Screening (`trueaxis::screen`): the false-alarm rate of each check on simulated clean data stays
//! under 1 %. The damaged variants of the shipped examples (made by `support::damage`) are tested
//! where each file is screened: `evaluate::positioning_screening`, `evaluate::ballbar_screening`,
//! `identify::campaign_screening`, `identify::robust_campaign`, `identify::direct_screening`,
//! `thermal::thermal_screening`.

mod false_alarms;
