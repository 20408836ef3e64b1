// The message helpers: percentages that never read "0 %" for a share above zero, numbers as
// typed, word lists.
#include <catch2/catch.hpp>

#include "tvid/util/text.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

TEST_CASE("a percentage has whole percent from 10 % up and two significant digits below", "[text]") {
    CHECK(readable_percent(0.38) == "38 %");
    CHECK(readable_percent(0.1) == "10 %");
    CHECK(readable_percent(1.5) == "150 %");
    CHECK(readable_percent(0.042) == "4.2 %");
    CHECK(readable_percent(0.0013) == "0.13 %");  // the swarm's "still fell" just above its 0.1 % threshold
    CHECK(readable_percent(0.0) == "0 %");
    CHECK(whole_percent(0.042) == "4 %");
    CHECK(number_text(0.1) == "0.1");
    CHECK(join_words({"a", "b", "c"}) == "a, b, c");
}

}  // namespace TVID_UNITY_ID
