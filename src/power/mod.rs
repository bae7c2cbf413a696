//! Power flow, the crate's subject (physics spec §10–11): what a link transmits to the
//! structure, the power at an interface point in time and per harmonic, the net power of an
//! actuator, the energy balance that checks them, stored energy, spectra and the
//! mode-resolved view.
//!
//! Everything here reads results — samples, harmonic amplitudes, the state of a run, modes
//! handed in — and nothing here solves. Each concept is one function, and every analysis
//! and the sweep compute it through that function:
//!
//! | concept | time samples | harmonic amplitudes |
//! | --- | --- | --- |
//! | link forces F_T, F_i | [`link::transmitted_force`], [`link::interface_force`] | [`link::transmitted_amplitude`], [`link::interface_amplitude`], [`link::link_harmonic`] |
//! | point power | [`point::mean_product`], [`point::midpoint_work`] | [`point::mean_power`], [`point::mean_power_from_acceleration`] |
//! | per harmonic | [`spectra::harmonics`], [`spectra::power_per_harmonic`], [`spectra::power_from_acceleration`] | the same on solved amplitudes |
//! | net power, dissipation | [`point::net_power`], [`point::damper_dissipation`] | [`point::net_power`], [`point::dissipated_power`] |
//! | balance | [`balance::EnergyBalance`] | [`balance::balance_error`] |
//! | stored energy | [`energy::StoredEnergy`] | — |
//! | modes | — | [`modal::decompose`] |
//! | non-periodic records | [`record::energy`], [`record::point_record`] (PSDs, H1 FRFs) | — |

pub mod balance;
pub mod energy;
pub mod link;
pub mod modal;
pub mod point;
pub mod record;
pub mod spectra;
