"""Every command's --help ends with an example that parses, whose input files ship with the project, and with its
exit codes; StationXML is --stationxml (--inventory kept as its old name); every subcommand takes -q and -v."""

from __future__ import annotations

import shlex
from pathlib import Path

import pytest

from pipeline import cli

PROJECT = Path(__file__).resolve().parents[2]
COMMANDS = ["run", *cli.SUBCOMMANDS]


def _parser(command: str):
    return cli.build_parser() if command == "run" else cli.SUBCOMMANDS[command][0]()


@pytest.mark.parametrize("command", COMMANDS)
def test_help_ends_with_an_example_and_the_exit_codes(command):
    text = _parser(command).format_help()
    assert "example:\n  screen " in text and "exit codes: 0 ok;" in text


@pytest.mark.parametrize("command", [*COMMANDS, "fragility_event"])
def test_each_example_parses_and_its_inputs_ship_with_the_project(command):
    words = shlex.split(cli.EXAMPLES[command])[1:]
    name = "fragility" if command == "fragility_event" else command
    if name != "run":
        assert words[0] == name
        words = words[1:]
    args = _parser(name).parse_args(words)
    for option in ("records", "blocks", "observed", "shakemap"):
        path = getattr(args, option, None)
        if path is not None:
            assert (PROJECT / path).exists(), f"{command}: {path}"


@pytest.mark.parametrize("command", ["run", "fragility", "chart", "event"])
def test_stationxml_is_named_so_and_the_old_name_still_works(command):
    required = {"run": ["--records", "r", "--blocks", "b"], "fragility": ["--records", "r", "--blocks", "b",
                "--im", "pga", "--levels", "auto"], "chart": [], "event": ["--shakemap", "s", "--blocks", "b",
                                                                       "--fragility", "f"]}[command]
    parser = _parser(command)
    assert "--stationxml" in parser.format_help()
    for flag in ("--stationxml", "--inventory"):
        assert parser.parse_args([*required, flag, "st.xml"]).inventory == Path("st.xml")


@pytest.mark.parametrize("command", list(cli.SUBCOMMANDS))
def test_every_subcommand_takes_quiet_and_verbose(command):
    text = _parser(command).format_help()
    assert "--quiet" in text and "--verbose" in text


def test_the_guides_list_of_subcommands_is_the_commands_own():
    """docs/user-guide.md lists every subcommand with the line ``screen --help`` gives it (generated, so that a new
    subcommand cannot be left out)."""
    import re
    from pathlib import Path

    from pipeline.cli.main import SUBCOMMAND_HELP

    guide = (Path(__file__).resolve().parents[2] / "docs" / "user-guide.md").read_text()
    listed = re.search(r"<!-- subcommands -->\n(.*?)\n<!-- /subcommands -->", guide, flags=re.S)
    expected = "\n".join(f"- `screen {name}`: {line}" for name, line in SUBCOMMAND_HELP.items())
    assert listed is not None and listed.group(1) == expected, f"paste into docs/user-guide.md:\n{expected}"
