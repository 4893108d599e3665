"""``lagrangian analyze`` of a system whose Hamiltonian would pass the size limit: the report
comes out, the part that grew listed among its failures with the option that raises the
limit (no assertion about speed: the part fails by a small --size-limit)."""

import json

from lagrangian.cli.main import main


def test_a_part_past_the_size_limit_is_listed_and_the_report_comes_out(capsys):
    argv = ["analyze", "n_link_pendulum:4", "--size-limit", "1000", "--search-degree", "0"]
    code = main([*argv, "--format", "json"])
    document = json.loads(capsys.readouterr().out)
    assert code == 0
    assert document["hamiltonian"] is None and document["hamilton_equations"] is None
    reason = document["failures"]["hamiltonian"]
    assert "W^-1 for the 4 x 4 mass matrix" in reason and "--size-limit" in reason
    assert document["momenta"] is not None and document["equilibria"] is not None
