"""Network tests: nodes and clients on two hosts (namespaces), loss, partitions, load."""
