// lib/verify/verify_report: the names of regions, order kinds and faults come from one table each,
// are distinct, and are what the JSON report writes.
#include "lib/verify/verify_report.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

namespace vrv {
namespace {

TEST(VerifyReportNames, EachKindHasItsOwnName) {
  std::set<std::string> regions, faults;
  for (Region r : {Region::outside, Region::interior, Region::silhouette, Region::tf_jump, Region::all})
    regions.insert(std::string(region_name(r)));
  EXPECT_EQ(regions, (std::set<std::string>{"outside", "interior", "silhouette", "tf_jump", "all"}));
  for (FaultKind f : {FaultKind::quantisation, FaultKind::half_step_offset, FaultKind::constant_floor,
                      FaultKind::first_order_border_band, FaultKind::jitter, FaultKind::error_at_tf_jumps,
                      FaultKind::missing_opacity_correction, FaultKind::swapped_channels, FaultKind::fitted})
    faults.insert(std::string(fault_name(f)));
  EXPECT_EQ(faults.size(), 9u);
  EXPECT_TRUE(faults.count("missing opacity correction"));
  EXPECT_TRUE(faults.count("fitted fault"));
  EXPECT_TRUE(faults.count("swapped channels"));
  EXPECT_NE(order_kind_name(OrderKind::reference), order_kind_name(OrderKind::self));
}

TEST(VerifyReportNames, TheJsonWritesTheNames) {
  VerifyReport rep;
  ChannelReport c;
  c.regions = {{Region::all, 4, {}}, {Region::tf_jump, 1, {}}};
  rep.channels.push_back(c);
  OrderReport o;
  o.kind = OrderKind::self;
  rep.orders.push_back(o);
  rep.faults.push_back({FaultKind::constant_floor, "why"});
  const auto j = to_json(rep);
  EXPECT_TRUE(j["images"][0]["regions"].contains("tf_jump"));
  EXPECT_EQ(j["orders"][0]["kind"], "self");
  EXPECT_EQ(j["faults"][0]["name"], "constant floor");
  EXPECT_EQ(rep.faults[0].name(), "constant floor");
  EXPECT_EQ(rep.channels[0].region(Region::tf_jump)->pixels, 1);
  EXPECT_EQ(rep.channels[0].region(Region::silhouette), nullptr);
}

}  // namespace
}  // namespace vrv
