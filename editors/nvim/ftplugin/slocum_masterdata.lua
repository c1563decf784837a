-- Slocum sensor list (masterdata, .cac) buffer settings: comments start with #.
require("gloc.ftplugin").hash_comments()
