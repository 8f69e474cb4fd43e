"""``mura serve``: the WebSocket realizer server and its protocol (BML in, feedback out)."""
