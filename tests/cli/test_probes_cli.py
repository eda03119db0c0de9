import subprocess
import sys

from typer.testing import CliRunner

from voe.cli.main import app

runner = CliRunner()


def test_help_does_not_import_torch():
    code = "import sys; from voe.cli.main import app; assert 'torch' not in sys.modules, 'torch imported'"
    subprocess.run([sys.executable, "-c", code], check=True)
    out = subprocess.run([sys.executable, "-m", "voe", "--help"], capture_output=True, text=True)
    assert out.returncode == 0 and "probes" in out.stdout


def test_list_shows_versioned_ids():
    res = runner.invoke(app, ["probes", "list"])
    assert res.exit_code == 0
    assert "Permanence-v2" in res.output and "suite core" in res.output


def test_generate_validate_show(tmp_path):
    out = tmp_path / "p"
    res = runner.invoke(app, ["probes", "generate", "--concept", "permanence", "--per-concept", "2",
                              "--size", "32", "--out", str(out), "--seed", "5"])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["probes", "validate", str(out)])
    assert res.exit_code == 0 and "valid" in res.output
    png, gif = tmp_path / "s.png", tmp_path / "s.gif"
    assert runner.invoke(app, ["probes", "show", str(out), "--set", "permanence-0001", "--out", str(png)]).exit_code == 0
    assert runner.invoke(app, ["probes", "show", str(out), "--set", "permanence-0001", "--out", str(gif)]).exit_code == 0
    assert png.read_bytes()[:4] == b"\x89PNG" and gif.read_bytes()[:3] == b"GIF"


def test_errors_are_one_line_with_nonzero_exit(tmp_path):
    out = subprocess.run([sys.executable, "-m", "voe", "probes", "generate", "--concept", "permanense",
                          "--out", str(tmp_path / "x")], capture_output=True, text=True)
    assert out.returncode == 1
    assert out.stderr.strip().count("\n") == 0 and "did you mean 'Permanence-v2'" in out.stderr
    out = subprocess.run([sys.executable, "-m", "voe", "probes", "validate", str(tmp_path / "none")],
                         capture_output=True, text=True)
    assert out.returncode == 1 and "does not exist" in out.stderr
