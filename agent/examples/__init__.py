"""Example agent scripts: how an agent uses mura (run them with ``python -m agent.examples.NAME``)."""
