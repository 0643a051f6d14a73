"""Sub-commands of the dptbd command line."""
