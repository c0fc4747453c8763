"""Reading records: obspy plug-ins, units, grouping into station recordings, processing."""
