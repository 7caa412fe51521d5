"""Reading and writing guardsim's files safely.

- :mod:`~guardsim.files.reading`: JSON, XML and text read within limits, every fault one line naming
  the file and the place;
- :mod:`~guardsim.files.schema`: the JSON Schemas of every document guardsim reads, and the check that
  turns a schema fault into that one line;
- :mod:`~guardsim.files.output`: outputs written to a temporary file and renamed into place.
"""
