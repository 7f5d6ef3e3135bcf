"""vmach — G-code verifier and virtual machine simulator."""

__version__ = "0.1.0"
