"""What a run leaves for a person: the hash-keyed run store (atomic files, validated on reuse),
field output for ParaView and the figures of each test. Below the lab tests, which write into it.
"""
