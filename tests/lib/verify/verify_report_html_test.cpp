// lib/verify/verify_report_html: the page's parts (escaping, base64, shell words), a page from a
// real verification of the toy renderer (its order, its images decoded again, nothing external,
// hostile file names escaped), and the checks of --report's path.  The page in a real browser:
// verify_report_html_browser_test.py (CTest label `browser`).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <boost/archive/iterators/binary_from_base64.hpp>
#include <boost/archive/iterators/transform_width.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "lib/io/image_module.h"
#include "lib/io/numbered_error_map.h"
#include "lib/verify/verify_report_html.h"
#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_toy {
namespace {

namespace fs = std::filesystem;

TEST(VerifyReportHtml, EscapesEveryMarkupCharacter) {
  EXPECT_EQ(html_escape("<img src=x onerror=\"a('b')\">&amp;"),
            "&lt;img src=x onerror=&quot;a(&#39;b&#39;)&quot;&gt;&amp;amp;");
  EXPECT_EQ(html_escape("r_0.1.exr"), "r_0.1.exr");
}

TEST(VerifyReportHtml, Base64IsRfc4648) {  // the RFC's own test vectors
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\0\xff", 2)), "AP8=");
}

TEST(VerifyReportHtml, ShellQuotesOnlyWhatNeedsIt) {
  EXPECT_EQ(shell_quote("--steps"), "--steps");
  EXPECT_EQ(shell_quote("r_0.1.exr"), "r_0.1.exr");
  EXPECT_EQ(shell_quote("my image.exr"), "'my image.exr'");
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
  EXPECT_EQ(shell_quote("$HOME"), "'$HOME'");
  EXPECT_EQ(shell_quote(""), "''");
}

std::string decode_base64(const std::string& text) {
  using namespace boost::archive::iterators;
  std::string body = text.substr(0, text.find('='));
  using Decoder = transform_width<binary_from_base64<std::string::const_iterator>, 8, 6>;
  std::string out(Decoder(body.begin()), Decoder(body.end()));
  out.resize(body.size() * 3 / 4);
  return out;
}

class VerifyReportPage : public VerifyToy {
 protected:
  static constexpr const char* kHostile = "<script>alert(1)</script>&\"'.exr";
  void SetUp() override {
    // Files of their own per test: CTest runs this fixture's tests in parallel processes (a shared
    // name raced: one test's rename found the other's temporary gone).
    const std::string tag = std::string("html_") + ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::vector<ImageWithStep> images = toy_images(scene, toy::Fault::half_step_offset, tag);
    images[0].name = kHostile;  // the name shown for the coarsest image
    report = verify_images(scene, images, options());
    FaultFit fit;  // a ranking row with markup in its text
    fit.id = "test", fit.name = "<i>entry</i>", fit.parameter = "p", fit.value = 0.25, fit.explained = 0.9;
    fit.description = "described <u>here</u>";
    report.fault_fits.push_back(fit);
    page = verify_report_html(report, {"vrv verify", {"cd /tmp", "vrv verify 'a<b>.exr'"}, {}});
  }
  VerifyReport report;
  std::string page;
};

TEST_F(VerifyReportPage, HasTheVerdictAndFaultFirstThenTheSectionsInOrder) {
  ASSERT_FALSE(report.pass);
  ASSERT_TRUE(has_fault(report, FaultKind::half_step_offset));
  const auto at = [&](const std::string& what) {
    const std::size_t p = page.find(what);
    EXPECT_NE(p, std::string::npos) << what;
    return p;
  };
  const std::size_t verdict = at("<span id=\"verdict-text\">" + std::string(verdict_name(report.verdict.verdict)));
  const std::size_t fault = at("<b>Fault: half-step offset</b>");
  const std::size_t plot = at("<svg id=\"convergence-plot\"");
  const std::size_t maps = at("<section id=\"error-maps\"");
  const std::size_t regions = at("<section id=\"regions\"");
  const std::size_t catalogue = at("<section id=\"catalogue\"");
  const std::size_t reproduce = at("<section id=\"reproduce\"");
  EXPECT_LT(verdict, fault);
  EXPECT_LT(fault, plot);
  EXPECT_LT(plot, maps);
  EXPECT_LT(maps, regions);
  EXPECT_LT(regions, catalogue);
  EXPECT_LT(catalogue, reproduce);
  EXPECT_NE(page.find("FAIL"), std::string::npos);
  // The plot: one point per (series, step) with a positive error: 4 against the reference, 3 differences.
  const std::regex circle("<circle ");
  EXPECT_EQ(std::distance(std::sregex_iterator(page.begin(), page.end(), circle), std::sregex_iterator()), 7);
}

TEST_F(VerifyReportPage, EscapesUserStrings) {
  EXPECT_EQ(page.find("<script"), std::string::npos);
  EXPECT_EQ(page.find("<i>entry</i>"), std::string::npos);
  EXPECT_NE(page.find("&lt;script&gt;alert(1)&lt;/script&gt;&amp;&quot;&#39;.exr"), std::string::npos);
  EXPECT_NE(page.find("described &lt;u&gt;here&lt;/u&gt;"), std::string::npos);
  EXPECT_NE(page.find("vrv verify &#39;a&lt;b&gt;.exr&#39;"), std::string::npos);
}

TEST_F(VerifyReportPage, NeedsNothingFromOutside) {
  // Every src is an inline PNG; no script, stylesheet link or frame; the only URL is the SVG's namespace.
  const std::regex src(R"re(\b(src|href)="([^"]*)")re");
  long sources = 0;
  for (auto it = std::sregex_iterator(page.begin(), page.end(), src); it != std::sregex_iterator(); ++it, ++sources)
    EXPECT_EQ((*it)[2].str().rfind("data:image/png;base64,", 0), 0u) << (*it)[2].str().substr(0, 60);
  EXPECT_EQ(sources, static_cast<long>(report.channels.size()) + 1);  // the error maps and the reference
  for (const char* tag : {"<link", "<iframe", "<object", "@import", "url("}) EXPECT_EQ(page.find(tag), std::string::npos) << tag;
  // Outside the inline images (whose base64 may hold "//"), no URL but the SVG's namespace.
  const std::string text = std::regex_replace(page, std::regex("data:image/png;base64,[^\"]*"), "data:");
  const std::regex url("(https?:)?//[a-zA-Z]");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), url); it != std::sregex_iterator(); ++it)
    EXPECT_EQ(text.substr(static_cast<std::size_t>(it->position()), 26), "http://www.w3.org/2000/svg");
}

TEST_F(VerifyReportPage, ErrorMapsDecodeToTheNumberedMapOfEachImage) {
  const std::regex img(R"re(<img class="error-map"[^>]*src="data:image/png;base64,([^"]*)")re");
  std::size_t k = 0;
  for (auto it = std::sregex_iterator(page.begin(), page.end(), img); it != std::sregex_iterator(); ++it, ++k) {
    const fs::path file = scratch() / fmt::format("report_map_{}.png", k);
    std::ofstream(file, std::ios::binary) << decode_base64((*it)[1].str());
    image_module::ReadRequest request;
    request.max_channels = 4;
    const image_module::ReadResult png = image_module::read_file(file, request);
    ASSERT_LT(k, report.channels.size());
    Image err(report.width, report.height);
    std::copy(report.channels[k].error.begin(), report.channels[k].error.end(), err.pixels.begin());
    const Image8 expected = numbered_error_map(err, report.channels[k].all().max);
    EXPECT_EQ(png.width, expected.width);
    EXPECT_EQ(png.height, expected.height);
    ASSERT_EQ(png.channels, 3);
    // The pixels themselves: the map's colours, byte for byte.
    for (std::size_t j = 0; j < expected.pixels.size(); j += 97)
      ASSERT_NEAR(png.floats[j] * 255, expected.pixels[j], 1e-3) << "byte " << j;
  }
  EXPECT_EQ(k, report.channels.size());
}

TEST_F(VerifyReportPage, ShowsTheCatalogueRankingWithItsFittedValue) {
  EXPECT_NE(page.find("<table id=\"catalogue-ranking\">"), std::string::npos);
  EXPECT_NE(page.find("<td class=\"num\">0.25</td>"), std::string::npos);
  EXPECT_NE(page.find("90.0 %"), std::string::npos);
}

TEST_F(VerifyReportPage, WritesTheFileWhole) {
  const fs::path file = scratch() / "report_test.html";
  write_verify_report_html(file, report, {"vrv verify", {}, {}});
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(text.substr(text.size() - 15), "</body></html>\n");
  for (const auto& e : fs::directory_iterator(scratch()))
    EXPECT_EQ(e.path().filename().string().find("report_test.html.tmp"), std::string::npos);
}

TEST(VerifyReportPath, RefusesADirectoryAnInputAndAPlaceInsideOut) {
  const fs::path dir = scratch() / "report_path";
  fs::create_directories(dir / "out");
  const fs::path input = dir / "image.exr";
  std::ofstream(input) << "x";
  EXPECT_NO_THROW(check_verify_report_path(dir / "r.html", {input}, dir / "out", "--report"));
  EXPECT_NO_THROW(check_verify_report_path(dir / "new" / "r.html", {}, {}, "--report"));  // made, as --out is
  const auto message = [&](const fs::path& p, const fs::path& out) {
    try {
      check_verify_report_path(p, {input}, out, "--report");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(dir, {}).find("is a directory"), std::string::npos);
  EXPECT_NE(message(dir / "." / "image.exr", {}).find("is the input"), std::string::npos);
  EXPECT_NE(message(dir / "out" / "r.html", dir / "out").find("replaced whole"), std::string::npos);
  EXPECT_NE(message(dir / "o2", dir / "o2").find("is also --out"), std::string::npos);
  EXPECT_EQ(message(dir / "ok.html", dir / "out"), "accepted");
}

}  // namespace
}  // namespace vrv::verify_toy
