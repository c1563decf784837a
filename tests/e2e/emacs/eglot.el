;;; eglot.el --- Emacs with Eglot, set up as docs/editors.md says  -*- lexical-binding: t; -*-

;; Run by tests/e2e/run: emacs --batch -q -l tests/e2e/emacs/eglot.el, with
;; GLOC_SETUP the guide's `emacs-eglot' block. Opens a GBASIC script first (so
;; Eglot 1.9 sends `gbasic' as the language id of every later file), then Fig. 2
;; as GLOC and comet's nsb3.mi: each must be read in its own language (no bogus
;; errors), and completion must insert what the file needs: `loads m_dep' →
;; `loads m_depth', `b_arg: d_t' → `b_arg: d_target_depth(m) 12', `m_dep' → `m_depth'.

(load (expand-file-name "common.el" (file-name-directory load-file-name)) nil t)

;; What a normal start does and batch mode skips: activate the installed packages
;; (Debian's elpa-eglot among them; `-q' keeps Debian's site files, which say where).
(package-initialize)
(load (getenv "GLOC_SETUP") nil t)

(defvar gloc-root (gloc-test-project))

(defun gloc-open (file)
  "Visit FILE of the project as a user does and let Eglot connect."
  (find-file (expand-file-name file gloc-root))
  ;; `eglot-ensure' connects from `post-command-hook', after the command that
  ;; visited the file; batch mode has no command loop, so run it here.
  (run-hooks 'post-command-hook)
  (gloc-test-wait (lambda () (and (fboundp 'eglot-current-server) (eglot-current-server))))
  (gloc-test-check (eglot-current-server) (format "Eglot manages %s" file) major-mode)
  (flymake-start))

(defun gloc-diagnostics (&optional seconds)
  "The Flymake diagnostics of this buffer after SECONDS (default 2) of server traffic."
  (gloc-test-wait (lambda () nil) (or seconds 2))
  (mapcar #'flymake-diagnostic-text (flymake-diagnostics)))

(defun gloc-errors ()
  "The Flymake errors among this buffer's diagnostics."
  (cl-remove-if-not (lambda (diagnostic) (eq (flymake-diagnostic-type diagnostic) 'eglot-error))
                    (flymake-diagnostics)))

(defun gloc-complete-and-choose (candidate)
  "Flush the typed text to the server (Eglot does so on an idle timer), ask
for completion at point and choose CANDIDATE; the candidates offered."
  (eglot--signal-textDocument/didChange)
  (gloc-test-choose (eglot-completion-at-point) candidate))

;;; GBASIC first: it starts the server.
(gloc-open "fig3.gbas")
(gloc-test-check (eq major-mode 'gbasic-mode) "fig3.gbas is in gbasic-mode" major-mode)
(gloc-test-check (null (gloc-diagnostics)) "Fig. 3 has no problems" (flymake-diagnostics))
(gloc-test-type-line 0 "x = m_dep")
(let ((offered (gloc-complete-and-choose "m_depth")))
  (gloc-test-check (member "m_depth" offered) "`m_dep' offers m_depth in GBASIC" offered)
  (gloc-test-check (equal (gloc-test-line) "x = m_depth") "choosing it gives `x = m_depth'"
                   (gloc-test-line)))

;;; GLOC, sent as `gbasic' by Eglot 1.9.
(gloc-open "fig2.gloc")
(gloc-test-check (eq major-mode 'gloc-mode) "fig2.gloc is in gloc-mode" major-mode)
(gloc-test-check (equal (eglot--language-id (eglot-current-server)) "gbasic")
                 "Eglot 1.9 sends the first mode's language id, `gbasic', for it too"
                 (eglot--language-id (eglot-current-server)))
(let ((problems (gloc-diagnostics)))
  (gloc-test-check (null problems) "Fig. 2 is read as GLOC: no problems" problems))
(gloc-test-type-line 0 "loads m_dep")
(let ((offered (gloc-complete-and-choose "m_depth")))
  (gloc-test-check (member "m_depth" offered) "`loads m_dep' offers m_depth by name"
                   (seq-take offered 10))
  (gloc-test-check (equal (try-completion "m_dep" offered) "m_depth")
                   "completion-at-point would complete `m_dep' to the common `m_depth'")
  (gloc-test-check (equal (gloc-test-line) "loads m_depth") "choosing it inserts the name: `loads m_depth'"
                   (gloc-test-line)))
;; A typo after it: the server's diagnostic reaches Flymake.
(gloc-test-type-line 0 "lodd 1.0,r0")
(eglot--signal-textDocument/didChange)
(flymake-start)
(let* ((texts (lambda () (mapcar #'flymake-diagnostic-text (flymake-diagnostics))))
       (found (gloc-test-wait
               (lambda ()
                 (cl-some (lambda (text) (string-match-p "did you mean `loadd`" text))
                          (funcall texts))))))
  (gloc-test-check found "typing `lodd' gets the server's \"did you mean `loadd`\""
                   (funcall texts)))
(set-buffer-modified-p nil)

;;; A mission, also sent as `gbasic'.
(gloc-open "missions/nsb3.mi")
(gloc-test-check (eq major-mode 'slocum-mission-mode) "nsb3.mi is in slocum-mission-mode" major-mode)
(let ((problems (gloc-diagnostics)))
  ;; Read as GBASIC it had 77 errors. As a mission: no error, and the one warning
  ;; `gloc run --mission' also prints (a sensor the embedded 2008 list lacks).
  (gloc-test-check (null (gloc-errors)) "nsb3.mi is read as a mission: no errors" problems)
  (gloc-test-check (and (= (length problems) 1) (string-match-p "S0106" (car problems)))
                   "its one warning is S0106, as `gloc run' prints" problems))
;; Line 67 is yo's `args_from_file' line; a new argument of yo under it.
(gloc-test-type-line 67 "    b_arg: d_t")
(let ((offered (gloc-complete-and-choose "d_target_depth")))
  (gloc-test-check (member "d_target_depth" offered) "`b_arg: d_t' offers d_target_depth" offered)
  (gloc-test-check (equal (gloc-test-line) "    b_arg: d_target_depth(m) 12")
                   "choosing it inserts `d_target_depth(m) 12' (no yasnippet: the default filled in)"
                   (gloc-test-line)))
;; Formatting keeps the glider's layout (it was rewritten as GBASIC before).
(set-buffer-modified-p nil)
(revert-buffer t t)
(let ((before (buffer-string)))
  (eglot-format-buffer)
  (gloc-test-check (equal (replace-regexp-in-string "[ \t]+$" "" before) (buffer-string))
                   "formatting nsb3.mi only removes trailing blanks"))
(set-buffer-modified-p nil)

(let ((server (eglot-current-server)))
  (when server (eglot-shutdown server)))
(gloc-test-finish)
