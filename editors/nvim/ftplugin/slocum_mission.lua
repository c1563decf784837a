-- Slocum mission (.mi) buffer settings: comments start with #.
require("gloc.ftplugin").hash_comments()
