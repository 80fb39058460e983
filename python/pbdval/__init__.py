"""pbdval's Python side: the external-engine protocol (docs/external-engines.md)."""
