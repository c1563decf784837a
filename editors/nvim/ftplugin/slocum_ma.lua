-- Slocum mission argument (.ma) buffer settings: comments start with #.
require("gloc.ftplugin").hash_comments()
