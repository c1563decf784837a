;;; gloc-mode.el --- Major modes for GLOC, GBASIC and Slocum mission files, served by gloc lsp  -*- lexical-binding: t; -*-

;; Version: 0.1.0
;; Package-Requires: ((emacs "27.1"))
;; Keywords: languages
;; URL: https://github.com/gloc/gloc (editors/emacs in the gloc repository)

;;; Commentary:

;; Major modes for the files of a Slocum glider pilot, each served by the
;; language server `gloc lsp' (diagnostics, completion, hover, definitions,
;; rename, formatting):
;;
;;   gbasic-mode             .gbas .bas .gbasic  GBASIC scripts
;;   gloc-mode               .gloc               GLOC assembly
;;   slocum-mission-mode     .mi                 mission files
;;   slocum-ma-mode          .ma                 mission argument files
;;   slocum-masterdata-mode  .cac, masterdata    sensor lists
;;
;; Loading this file registers `gloc lsp' with Eglot and with lsp-mode
;; (whichever is installed, when it loads); start either from the mode hooks:
;;
;;   (add-to-list 'load-path "/path/to/gloc/editors/emacs")
;;   (require 'gloc-mode)
;;   (add-hook 'gloc-base-mode-hook #'eglot-ensure)   ; or #'lsp
;;
;; The modes hold highlighting and comment syntax only; every answer about the
;; languages comes from the server (docs/editors.md in the gloc repository).

;;; Code:

(defgroup gloc nil
  "GLOC, GBASIC and Slocum mission files, with the gloc language server."
  :group 'languages
  :prefix "gloc-")

(defcustom gloc-program "gloc"
  "The gloc binary: a bare name is looked up on `exec-path'."
  :type 'string)

(define-derived-mode gloc-base-mode prog-mode "gloc"
  "Parent of the five gloc modes: `gloc-base-mode-hook' runs in each of them,
one place to start Eglot or lsp-mode for all."
  (setq-local comment-start "# "))

(defconst gloc-language-ids
  '((gbasic-mode . "gbasic")
    (gloc-mode . "gloc")
    (slocum-mission-mode . "slocum_mission")
    (slocum-ma-mode . "slocum_ma")
    (slocum-masterdata-mode . "slocum_masterdata"))
  "Each mode's language id for the server.
The server reads a file with one of gloc's extensions by its extension, whatever
id it is sent, so a client that sends one id for all of them still works.")

(defconst gloc--sensor-read-only "\\_<[mx]_[[:alnum:]_]+\\_>")
(defconst gloc--sensor-writable "\\_<\\(?:sci\\|xs\\|cc\\|dc\\|dhs\\|[cfus]\\)_[[:alnum:]_]+\\_>")

;;; GBASIC

(defvar gbasic-mode-syntax-table
  (let ((table (make-syntax-table)))
    (modify-syntax-entry ?' "<" table)
    (modify-syntax-entry ?\n ">" table)
    (modify-syntax-entry ?\" "\"" table)
    (modify-syntax-entry ?_ "_" table)
    table)
  "Syntax table of `gbasic-mode': `'' starts a comment.")

(defconst gbasic-font-lock-keywords
  `((,(regexp-opt '("if" "then" "elseif" "else" "endif" "while" "wend" "do" "loop" "until"
                    "for" "to" "step" "next" "exit" "yield" "print" "let" "dim" "const"
                    "as" "and" "or" "not" "mod" "end" "goto" "label")
                  'symbols)
     . font-lock-keyword-face)
    (,(regexp-opt '("integer" "float") 'symbols) . font-lock-type-face)
    (,gloc--sensor-read-only . font-lock-constant-face)
    (,gloc--sensor-writable . font-lock-variable-name-face))
  "Highlighting of `gbasic-mode'.")

;;;###autoload
(define-derived-mode gbasic-mode gloc-base-mode "GBASIC"
  "Major mode for GBASIC scripts of the Slocum glider (`gloc lsp' serves it)."
  (setq-local comment-start "' ")
  (setq-local comment-start-skip "'+\\s-*")
  (setq-local font-lock-defaults '(gbasic-font-lock-keywords nil t))
  )

;;; GLOC and the hash-comment files

(defvar gloc-hash-comment-syntax-table
  (let ((table (make-syntax-table)))
    (modify-syntax-entry ?# "<" table)
    (modify-syntax-entry ?\n ">" table)
    (modify-syntax-entry ?\" "\"" table)
    (modify-syntax-entry ?_ "_" table)
    table)
  "Syntax table of the modes whose comments start with `#'.")

(defconst gloc-font-lock-keywords
  `((,(regexp-opt '("nregs" "nblbs" "nlbls" "ninstr" "nmem" "label") 'symbols)
     . font-lock-preprocessor-face)
    (,(regexp-opt '("cbr" "jumpi" "jump" "yield" "halt") 'symbols) . font-lock-keyword-face)
    (,(regexp-opt '("loadi" "loadd" "loadm" "storem" "loads" "stores" "mov" "add" "sub" "mul"
                    "div" "mod" "neg" "abs" "sqrt" "min" "max" "i2d" "d2i" "and" "or" "xor"
                    "not" "cmpeq" "cmpne" "cmplt" "cmple" "cmpgt" "cmpge" "print" "prints"
                    "write" "writes" "nop")
                  'symbols)
     . font-lock-builtin-face)
    ("\\_<r[0-9]+\\_>" . font-lock-variable-name-face))
  "Highlighting of `gloc-mode'.")

;;;###autoload
(define-derived-mode gloc-mode gloc-base-mode "GLOC"
  "Major mode for GLOC assembly of the Slocum glider (`gloc lsp' serves it)."
  :syntax-table gloc-hash-comment-syntax-table
  (setq-local comment-start "# ")
  (setq-local comment-start-skip "#+\\s-*")
  (setq-local font-lock-defaults '(gloc-font-lock-keywords nil t))
  )

(defconst slocum-mission-font-lock-keywords
  `(("^\\s-*\\(behavior:\\|b_arg:\\|sensor:\\|behavior_name=\\)" 1 font-lock-keyword-face)
    ("<\\(?:start\\|end\\):[a-z_]+>" . font-lock-keyword-face)
    ("behavior:\\s-*\\([[:alnum:]_]+\\)" 1 font-lock-function-name-face)
    (,gloc--sensor-read-only . font-lock-constant-face)
    (,gloc--sensor-writable . font-lock-variable-name-face))
  "Highlighting of mission, argument and sensor-list files.")

;;;###autoload
(define-derived-mode slocum-mission-mode gloc-base-mode "Mission"
  "Major mode for Slocum mission files (`.mi'), served by `gloc lsp'."
  :syntax-table gloc-hash-comment-syntax-table
  (setq-local comment-start "# ")
  (setq-local font-lock-defaults '(slocum-mission-font-lock-keywords))
  )

;;;###autoload
(define-derived-mode slocum-ma-mode gloc-base-mode "Mission args"
  "Major mode for Slocum mission argument files (`.ma'), served by `gloc lsp'."
  :syntax-table gloc-hash-comment-syntax-table
  (setq-local comment-start "# ")
  (setq-local font-lock-defaults '(slocum-mission-font-lock-keywords))
  )

;;;###autoload
(define-derived-mode slocum-masterdata-mode gloc-base-mode "Sensors"
  "Major mode for Slocum sensor lists (`masterdata', `.cac'), served by `gloc lsp'."
  :syntax-table gloc-hash-comment-syntax-table
  (setq-local comment-start "# ")
  (setq-local font-lock-defaults '(slocum-mission-font-lock-keywords))
  )

;;;###autoload
(progn
  (add-to-list 'auto-mode-alist '("\\.\\(?:gbas\\|gbasic\\|bas\\)\\'" . gbasic-mode))
  (add-to-list 'auto-mode-alist '("\\.gloc\\'" . gloc-mode))
  (add-to-list 'auto-mode-alist '("\\.[mM][iI]\\'" . slocum-mission-mode))
  (add-to-list 'auto-mode-alist '("\\.[mM][aA]\\'" . slocum-ma-mode))
  (add-to-list 'auto-mode-alist '("\\.[cC][aA][cC]\\'" . slocum-masterdata-mode))
  (add-to-list 'auto-mode-alist '("/masterdata\\'" . slocum-masterdata-mode)))

;;; The language server, for Eglot and for lsp-mode

(defun gloc--server-command (&rest _)
  "The command that starts the language server."
  (list gloc-program "lsp"))

(with-eval-after-load 'eglot
  (defvar eglot-server-programs)
  ;; One entry for all five modes: one server for a project's scripts and missions.
  (add-to-list 'eglot-server-programs
               (cons (mapcar (lambda (pair) (list (car pair) :language-id (cdr pair)))
                             gloc-language-ids)
                     #'gloc--server-command)))

(with-eval-after-load 'lsp-mode
  (defvar lsp-language-id-configuration)
  (declare-function lsp-register-client "lsp-mode")
  (declare-function make-lsp-client "lsp-mode")
  (declare-function lsp-stdio-connection "lsp-mode")
  (declare-function lsp-activate-on "lsp-mode")
  (dolist (pair gloc-language-ids)
    (add-to-list 'lsp-language-id-configuration pair))
  (lsp-register-client
   (make-lsp-client :new-connection (lsp-stdio-connection #'gloc--server-command)
                    :activation-fn (apply #'lsp-activate-on (mapcar #'cdr gloc-language-ids))
                    :server-id 'gloc)))

(provide 'gloc-mode)
;;; gloc-mode.el ends here
