"""Standard input is model text, never a file name; examples built to a size."""

import io

from lagrangian.cli.main import main


def run(capsys, monkeypatch, argv, stdin=""):
    monkeypatch.setattr("sys.stdin", io.StringIO(stdin))
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_a_path_piped_to_standard_input_is_not_opened(tmp_path, capsys, monkeypatch):
    secret = tmp_path / "shadow"
    secret.write_text("root:$6$very-secret-hash:19000:0:99999:7:::\n")
    code, out, error = run(capsys, monkeypatch, ["derive", "-"], stdin=str(secret))
    assert code == 2
    assert "very-secret-hash" not in out + error  # the file was never read
    assert "standard input" in error


def test_model_text_on_standard_input(capsys, monkeypatch):
    model = "coordinates: [x]\nparameters: {k: 1}\nkinetic: x_dot**2/2\npotential: k*x**2/2\n"
    code, out, _ = run(capsys, monkeypatch, ["derive", "-"], stdin=model)
    assert code == 0 and "x_ddot" in out


def test_an_example_built_to_a_size(capsys, monkeypatch):
    code, out, _ = run(capsys, monkeypatch, ["derive", "n_link_pendulum:5"])
    equations = [line for line in out.splitlines() if line.endswith("= 0")]
    assert code == 0 and len(equations) == 5 and "m5 = 1" in out.splitlines()[-1]
    code, out, _ = run(capsys, monkeypatch, ["derive", "examples/n_link_pendulum:2"])
    assert code == 0 and len([line for line in out.splitlines() if line.endswith("= 0")]) == 2
    code, _, error = run(capsys, monkeypatch, ["derive", "double_pendulum:5"])
    assert code == 2 and "has no size" in error
    code, _, error = run(capsys, monkeypatch, ["derive", "n_link_pendulum:many"])
    assert code == 2 and "whole number" in error


def test_standard_input_in_toml_with_input_format(capsys, monkeypatch):
    model = 'coordinates = ["x"]\nkinetic = "x_dot**2/2"\npotential = "x**2/2"\n'
    code, out, _ = run(capsys, monkeypatch, ["derive", "-", "--input-format", "toml"], stdin=model)
    assert code == 0 and "x + x_ddot = 0" in out
    # without it the text is read as YAML, which it is not: a clear refusal, exit 2
    code, _, error = run(capsys, monkeypatch, ["derive", "-"], stdin=model)
    assert code == 2 and "standard input" in error
