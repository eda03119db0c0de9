"""Open report.html in headless Chromium and check every figure decodes and nothing is broken."""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from voe.report.build import build_report

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]

# Appended to a copy of the page: after load, record how many images decoded and which did not.
PROBE = """<script>
window.addEventListener('load', () => {
  const imgs = Array.from(document.images);
  const bad = imgs.filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.alt);
  const ext = Array.from(document.querySelectorAll('[src],[href]'))
    .map(e => e.getAttribute('src') || e.getAttribute('href')).filter(u => !u.startsWith('data:'));
  document.body.setAttribute('data-check',
    'imgs=' + imgs.length + ';ok=' + (imgs.length - bad.length) + ';bad=' + bad.join('|') +
    ';external=' + ext.length + ';tables=' + document.querySelectorAll('table').length);
});
</script>"""


def _chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.mark.slow
def test_report_html_renders_in_chromium(fake_runs, tmp_path):
    exe = _chromium()
    if exe is None:
        pytest.skip("headless Chromium not installed (Debian: apt-get install -y chromium)")
    out = tmp_path / "rep"
    build_report([fake_runs[k] for k in ("cheating", "blind", "random-0")], out, n_boot=500)
    html = (out / "report.html").read_text()
    n_figs = len(list((out / "figures").glob("*.png")))
    page = tmp_path / "probe.html"
    page.write_text(html.replace("</body>", PROBE + "</body>"))
    res = subprocess.run([exe, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}",
                          "--virtual-time-budget=10000", "--dump-dom", page.as_uri()],
                         capture_output=True, text=True, timeout=120)
    m = re.search(r'data-check="([^"]*)"', res.stdout)
    assert m, f"no marker in DOM (chromium rc={res.returncode}): {res.stderr[-500:]}"
    check = dict(kv.split("=", 1) for kv in m.group(1).split(";"))
    assert int(check["imgs"]) == n_figs == 7  # heatmap, conditions, 3 looking-time, 2 filmstrips
    assert check["ok"] == check["imgs"] and check["bad"] == "", check
    assert check["external"] == "0" and int(check["tables"]) >= 3

    shot = tmp_path / "shot.png"
    subprocess.run([exe, *FLAGS, f"--user-data-dir={tmp_path / 'profile2'}", "--window-size=1200,3000",
                    f"--screenshot={shot}", (out / "report.html").as_uri()],
                   capture_output=True, timeout=120)
    assert shot.is_file() and shot.stat().st_size > 10_000
