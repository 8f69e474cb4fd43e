"""Constants of the realizer-server tests."""

#: Seconds any one wait of these tests may take (a bound against hangs, not a measurement).
TIMEOUT = 60.0
