#include "lib/verify/convergence_orders.h"

#include <fmt/format.h>

#include "lib/verify/channel_errors.h"

namespace vrv {
namespace {

OrderReport against_reference(const VerifyReport& rep, std::size_t images, int nc, int c, const std::string& channel,
                              const VerifyOptions& opt) {
  OrderReport against;
  against.channel = channel;
  against.kind = OrderKind::reference;
  for (std::size_t k = 0; k < images; ++k) {
    const ChannelReport& r = rep.channels[k * nc + c];
    if (r.at_floor) continue;  // no order claimed below the quantisation floor
    against.steps.push_back(r.step);
    against.errors.push_back(metric_value(r.all(), opt.order_metric));
  }
  against.fit = fit_order(against.steps, against.errors);
  against.judgement = judge(against.steps, against.errors, against.fit, {opt.expected_order, opt.order_tolerance});
  if (against.steps.size() < images && against.steps.size() < 2)
    against.judgement.reason += " (the finer images are at their quantisation floor)";
  return against;
}

OrderReport self_convergence(const std::vector<const ImageWithStep*>& sorted, int c, const std::string& channel,
                             double background, const VerifyOptions& opt) {
  OrderReport self;
  self.channel = channel;
  self.kind = OrderKind::self;
  for (std::size_t k = 0; k + 1 < sorted.size(); ++k) {
    self.steps.push_back(sorted[k]->step);
    self.errors.push_back(difference_metric(sorted[k]->image, sorted[k + 1]->image, c, background, opt));
  }
  if (!sorted.empty()) {
    std::vector<double> all_steps;
    for (const auto* im : sorted) all_steps.push_back(im->step);
    self.fit = self_convergence_order(all_steps, self.errors);
    self.judgement = judge(self.steps, self.errors, self.fit, {opt.expected_order, opt.order_tolerance});
  }
  return self;
}

}  // namespace

void judge_orders(VerifyReport& rep, const std::vector<const ImageWithStep*>& sorted,
                  const std::vector<std::string>& names, const std::vector<double>& backgrounds,
                  const VerifyOptions& opt) {
  const int nc = static_cast<int>(names.size());
  bool judged = false;
  for (int c = 0; c < nc; ++c) {
    OrderReport against = against_reference(rep, sorted.size(), nc, c, names[c], opt);
    OrderReport self = self_convergence(sorted, c, names[c], backgrounds[c], opt);
    if (!judged || severity(against.judgement.verdict) > severity(rep.verdict.verdict)) {
      rep.verdict = against.judgement;
      rep.verdict_channel = against.channel;
      judged = true;
    }
    rep.orders.push_back(std::move(against));
    rep.orders.push_back(std::move(self));
  }
  if (opt.expected_order && rep.verdict.verdict != Verdict::converges)
    rep.failures.push_back(fmt::format("expected convergence at order {:g}; channel {} {}: {}",
                                       *opt.expected_order, rep.verdict_channel,
                                       verdict_name(rep.verdict.verdict), rep.verdict.reason));
}

}  // namespace vrv
