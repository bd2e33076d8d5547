// report.json and report.html of the demo; see report.h.
#include "demo/report.h"

#include <fmt/format.h>

#include <filesystem>

#include "host/util/image_io.h"

namespace lorgnette::demo {
namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string number(const nlohmann::json& j, const char* key, const char* fmtstr = "{:.2f}") {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number()) return "–";
  return fmt::format(fmt::runtime(fmtstr), j[key].get<double>());
}

std::string image_row(const std::vector<std::string>& files, int width) {
  std::string out;
  for (const auto& f : files)
    out += fmt::format("<a href=\"{0}\"><img src=\"{0}\" width=\"{1}\" alt=\"{0}\"></a>\n", escape(f), width);
  return out;
}

// The scale's source and the fit advice from the placement (#44): one line for the scale, one table
// row per rule; "" when the placement has neither.
std::string scale_and_advice(const nlohmann::json& fit) {
  if (!fit.is_object() || !fit.contains("scale_source")) return "";
  const std::string policy = fit.value("scale_policy", "");
  std::string out = fmt::format(
      "<h2>Size and fit</h2>\n<p>Scale from <b>{}</b>: {} &plusmn; {} mm per unit; PD {} &plusmn; {} mm. "
      "{}</p>\n",
      escape(fit["scale_source"].is_string() ? fit["scale_source"].get<std::string>() : "?"),
      number(fit, "mm_per_unit", "{:.4g}"), number(fit, "mm_per_unit_uncertainty", "{:.2g}"),
      number(fit, "pd_mm", "{:.1f}"), number(fit, "pd_uncertainty_mm", "{:.1f}"),
      policy == "true-size"
          ? "The frame is shown at its real size."
          : "The frame is stretched to the face's width: the size shown is not its real size.");
  if (!fit.contains("advice") || !fit["advice"].is_object()) return out;
  out += "<table>\n";
  for (const auto& r : fit["advice"].value("rules", nlohmann::json::array()))
    if (r.is_object())
      out += fmt::format("<tr><td>{}</td><td>{}</td></tr>\n", escape(r.value("verdict", "")),
                         escape(r.value("text", "")));
  return out + "</table>\n";
}

}  // namespace

nlohmann::json DemoReport::to_json() const {
  nlohmann::json seconds = nlohmann::json::object(), cpu = nlohmann::json::object();
  double total = 0.0, cpu_total = 0.0;
  for (const auto& s : stages) {
    seconds[s.name] = s.seconds;
    cpu[s.name] = s.cpu_seconds;
    total += s.seconds;
    cpu_total += s.cpu_seconds;
  }
  seconds["total"] = total;
  cpu["total"] = cpu_total;
  return {{"version", version},
          {"device", device},
          {"machine", machine},
          {"ok", ok},
          {"message", message},
          {"seconds", seconds},
          {"cpu_seconds", cpu},
          {"psnr", psnr},
          {"ssim", ssim},
          {"heldout_views", heldout_views},
          {"train",
           {{"steps", train_steps},
            {"seconds", train_seconds},
            {"budget", train_budget},
            {"model_mb", model_mb}}},
          {"fit", fit},
          {"ground_truth", ground_truth},
          {"config", config},
          {"files",
           {{"orbit_mp4", orbit_mp4},
            {"contact_sheet", contact_sheet},
            {"glasses_preview", glasses_preview},
            {"loss_chart", loss_chart},
            {"debug_views", debug_views},
            {"heldout_images", heldout_images}}}};
}

std::string render_report_html(const DemoReport& r) {
  std::string stages = "<tr><th>stage</th><th>wall</th><th>CPU</th></tr>\n";
  double total = 0.0, cpu_total = 0.0;
  for (const auto& s : r.stages) {
    stages += fmt::format("<tr><td>{}</td><td>{:.1f} s</td><td>{:.1f} s</td></tr>\n", escape(s.name),
                          s.seconds, s.cpu_seconds);
    total += s.seconds;
    cpu_total += s.cpu_seconds;
  }
  stages += fmt::format("<tr><th>total</th><th>{:.1f} s</th><th>{:.1f} s</th></tr>\n", total, cpu_total);
  std::string status = r.ok ? "<p class=ok>The fit succeeded.</p>"
                            : fmt::format("<p class=bad>Not complete: {}</p>", escape(r.message));
  std::string video = r.orbit_mp4.empty()
                          ? ""
                          : fmt::format(
                                "<video src=\"{0}\" controls loop autoplay muted width=\"480\"></video>"
                                "<p><a href=\"{0}\">{0}</a></p>",
                                escape(r.orbit_mp4));
  std::string sheet = r.contact_sheet.empty() ? "" : image_row({r.contact_sheet}, 960);
  return fmt::format(
      R"(<!doctype html>
<html><head><meta charset="utf-8"><title>Lorgnette demo report</title>
<style>body{{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}}
table{{border-collapse:collapse}}td,th{{padding:2px 12px;text-align:left;border-bottom:1px solid #ddd}}
.ok{{color:#185}} .bad{{color:#b22}} img{{margin:4px;border:1px solid #ccc}}
pre{{background:#f6f6f6;padding:8px;overflow:auto;font-size:12px}}</style></head><body>
<h1>Lorgnette demo</h1>
{status}
<p>Device: {device} &middot; Machine: {machine} &middot; Lorgnette {version}</p>
<h2>Orbit</h2>
{video}
{sheet}
<h2>Numbers</h2>
<table>
<tr><td>held-out PSNR</td><td>{psnr:.2f} dB over {views} views (SSIM {ssim:.3f})</td></tr>
<tr><td>training</td><td>{steps} steps in {train_s:.1f} s, model {mb:.1f} MB ({budget})</td></tr>
<tr><td>estimated PD</td><td>{pd} mm</td></tr>
<tr><td>remaining penetration</td><td>{pen} mm</td></tr>
<tr><td>views used by the fit</td><td>{used}</td></tr>
</table>
{size_fit}
<h2>Stage times</h2>
<table>{stages}</table>
<h2>Training</h2>
{loss}
{heldout}
<h2>Fit: detected and reprojected landmarks</h2>
{debug}
<h2>Glasses</h2>
{preview}
<h2>Fit details</h2>
<pre>{fit}</pre>
<h2>Against ground truth</h2>
<pre>{gt}</pre>
</body></html>
)",
      fmt::arg("status", status), fmt::arg("device", escape(r.device)),
      fmt::arg("machine", escape(r.machine)), fmt::arg("version", escape(r.version)),
      fmt::arg("video", video), fmt::arg("sheet", sheet), fmt::arg("psnr", r.psnr),
      fmt::arg("views", r.heldout_views), fmt::arg("ssim", r.ssim), fmt::arg("steps", r.train_steps),
      fmt::arg("train_s", r.train_seconds), fmt::arg("budget", escape(r.train_budget)),
      fmt::arg("mb", r.model_mb), fmt::arg("pd", number(r.fit, "pd_mm", "{:.1f}")),
      fmt::arg("pen", number(r.fit, "penetration_mm")),
      fmt::arg("used", r.fit.is_object() && r.fit.contains("views_used") ? r.fit["views_used"].dump() : "–"),
      fmt::arg("stages", stages), fmt::arg("size_fit", scale_and_advice(r.fit)),
      fmt::arg("loss", r.loss_chart.empty() ? "" : image_row({r.loss_chart}, 640)),
      fmt::arg("heldout", image_row(r.heldout_images, 480)), fmt::arg("debug", image_row(r.debug_views, 240)),
      fmt::arg("preview", r.glasses_preview.empty() ? "" : image_row({r.glasses_preview}, 480)),
      fmt::arg("fit", escape(r.fit.dump(2))), fmt::arg("gt", escape(r.ground_truth.dump(2))));
}

void write_report(const std::string& dir, const DemoReport& report) {
  write_text_file_atomic((std::filesystem::path(dir) / "report.json").string(),
                         report.to_json().dump(2) + "\n");
  write_text_file_atomic((std::filesystem::path(dir) / "report.html").string(), render_report_html(report));
}

}  // namespace lorgnette::demo
