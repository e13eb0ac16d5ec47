"""Studies over many configurations of one problem: which failures a swarm
survives, and where its CubeSats should dock.

A study calls the simulation, allocation and budget layers for each case and
returns typed results; the workflows layer runs it and the report draws it.
"""
