#pragma once
// The excitations a bench plays, as shapes on a time grid and scaled to an RMS within a
// range: a linear chirp, a maximum-length PRBS and a Schroeder-phased multisine over a
// band (the standard signals of MATLAB's idinput and of Pintelon & Schoukens, "System
// Identification: A Frequency Domain Approach", ch. 5).

#include <cstddef>
#include <optional>
#include <vector>

namespace tvid {

/// t_k = k / sample_rate, k = 0 .. samples - 1.
std::vector<double> excitation_time_grid(std::size_t samples, double sample_rate);

/// sin(2π (f_low t + (f_high − f_low) t² / (2 T))): the frequency sweeps linearly from f_low
/// at t = 0 to f_high at the last sample T.
std::vector<double> chirp_shape(const std::vector<double>& time, double f_low, double f_high);

/// ±1 from a maximum-length linear feedback shift register (the smallest of order 3 to 24
/// whose period covers the record), one bit per round(sample_rate / (2 f_high)) samples, so
/// that its power is flat to about f_high (idinput's band [0, f_high / Nyquist]).
std::vector<double> prbs_shape(std::size_t samples, double sample_rate, double f_high);

/// Σ_k cos(2π f_k t + φ_k) over the frequencies f_k = k / T of the record's grid (T its
/// length in time: samples / sample_rate) within [f_low, f_high], equal amplitudes, with
/// Schroeder's phases φ_k = −π k'(k' − 1) / K (k' = 1..K) that keep the crest factor low.
std::vector<double> schroeder_multisine_shape(const std::vector<double>& time, double sample_rate, double f_low,
                                              double f_high);

/// base + g · shape, clipped to [low, high], with the gain g > 0 that makes the RMS about
/// base equal `rms` (bisection: the clipped RMS rises with g). Nothing when the range
/// cannot hold that RMS (even a shape clipped to a square wave between the limits falls
/// short); `reachable` then gets the largest RMS it can reach.
std::optional<std::vector<double>> scaled_excitation(const std::vector<double>& shape, double base, double rms,
                                                     double low, double high, double* reachable = nullptr);

/// The RMS of `v` about `base`.
double rms_about(const std::vector<double>& v, double base);

}  // namespace tvid
