// Channels of several recordings laid end to end (channels/recording_spans.hpp): a delay,
// a slope and a crank-angle lookup read each recording as that recording alone would,
// never the neighbour across the joint.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "tvid/channels/channel_delay.hpp"
#include "tvid/channels/crank_angle_channels.hpp"
#include "tvid/channels/recording_spans.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using tvid::RowSpan;

namespace {

// Two recordings of 20 samples at 1 ms, the second's clock moved to follow the first.
struct TwoRecordings {
    std::vector<double> time, value;
    std::vector<double> first_time, first_value, second_time, second_value;
    std::vector<RowSpan> spans{{0, 20}, {20, 40}};
    TwoRecordings() {
        for (int k = 0; k < 20; ++k) {
            first_time.push_back(0.001 * k);
            first_value.push_back(std::sin(0.4 * k));
            second_time.push_back(0.001 * k);
            second_value.push_back(5 + std::cos(0.7 * k));
        }
        time = first_time;
        value = first_value;
        for (int k = 0; k < 20; ++k) {
            time.push_back(second_time[static_cast<std::size_t>(k)] + 0.020);
            value.push_back(second_value[static_cast<std::size_t>(k)]);
        }
    }
};

}  // namespace

TEST_CASE("slopes are one-sided at each recording's ends", "[channels][recordings]") {
    const TwoRecordings r;
    const std::vector<double> joined = tvid::sample_slopes(r.value, r.time, r.spans);
    const std::vector<double> first = tvid::sample_slopes(r.first_value, r.first_time);
    const std::vector<double> second = tvid::sample_slopes(r.second_value, r.second_time);
    for (std::size_t i = 0; i < 20; ++i) {
        CHECK(joined[i] == first[i]);
        CHECK(joined[20 + i] == Approx(second[i]).epsilon(1e-9));  // the moved clock rounds the intervals
    }
    // One span is the whole table: the plain rule, bit for bit.
    CHECK(tvid::sample_slopes(r.value, r.time, {{0, 40}}) == tvid::sample_slopes(r.value, r.time));
}

TEST_CASE("a delay is held at each recording's own ends", "[channels][recordings]") {
    const TwoRecordings r;
    for (double delay : {0.0025, -0.0025, 0.004, -0.0041}) {
        INFO("delay " << delay);
        std::vector<double> joined, first, second;
        tvid::delay_channel(r.value, r.time, r.spans, delay, joined);
        tvid::delay_channel(r.first_value, r.first_time, delay, first);
        tvid::delay_channel(r.second_value, r.second_time, delay, second);
        REQUIRE(joined.size() == 40);
        for (std::size_t i = 0; i < 20; ++i) {
            CHECK(joined[i] == first[i]);
            CHECK(joined[20 + i] == Approx(second[i]).epsilon(1e-9));
        }
        // Read across the joint, the first recording's end would see the second's start.
        std::vector<double> across;
        tvid::delay_channel(r.value, r.time, delay, across);
        CHECK((delay > 0 ? across[19] != joined[19] : across[20] != joined[20]));
    }
}

TEST_CASE("a crank-angle channel holds each recording's ends across the gap", "[channels][recordings]") {
    // Two recordings of 11 samples, 72 deg apart; the second a cycle (720 deg) after the first.
    std::vector<double> angle, p;
    for (int k = 0; k <= 10; ++k) {
        angle.push_back(72.0 * k);
        p.push_back(1 + k);
    }
    for (int k = 0; k <= 10; ++k) {
        angle.push_back(720.0 + 720.0 + 72.0 * k);
        p.push_back(100 + k);
    }
    const std::vector<RowSpan> spans{{0, 11}, {11, 22}};
    const tvid::CrankAngleChannels joined = tvid::CrankAngleChannels::end_to_end(angle, {p}, spans);
    std::size_t cursor = 0;
    CHECK(joined.at(0, 36.0, cursor) == 1.5);     // inside the first recording: linear
    CHECK(joined.at(0, 720.0, cursor) == 11.0);   // its last sample
    CHECK(joined.at(0, 725.0, cursor) == 11.0);   // a throw past its end: held, as a recording alone holds it
    CHECK(joined.at(0, 1070.0, cursor) == 11.0);  // up to the gap's middle
    CHECK(joined.at(0, 1090.0, cursor) == 100.0); // from there the second recording's first value
    CHECK(joined.at(0, 1435.0, cursor) == 100.0);
    CHECK(joined.at(0, 1476.0, cursor) == 100.5);
    CHECK(joined.at(0, 5000.0, cursor) == 110.0);
    // One recording: the plain channel.
    const tvid::CrankAngleChannels one = tvid::CrankAngleChannels::end_to_end(angle, {p}, {{0, 22}});
    CHECK(one.angle() == angle);
}

TEST_CASE("the mean sample interval leaves out the gaps between recordings", "[channels][recordings]") {
    const TwoRecordings r;
    CHECK(tvid::mean_sample_interval(r.time, r.spans) == Approx(0.001));
    std::vector<double> far = r.time;
    for (std::size_t i = 20; i < 40; ++i) far[i] += 100.0;  // the second clock 100 s later
    CHECK(tvid::mean_sample_interval(far, r.spans) == Approx(0.001));
    CHECK(tvid::mean_sample_interval(r.time, {{0, 40}}) == (r.time.back() - r.time.front()) / 39.0);
}

}  // namespace TVID_UNITY_ID
